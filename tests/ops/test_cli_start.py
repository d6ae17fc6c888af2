"""A command of `trikecert` (audit-verify, create-user, notify, ...) starts without reading the web
framework or Alembic: a third of its start (0.6 -> 0.4 s here), which every operator's command and
every process the tests start would pay. Alembic comes in only when a command migrates or meets a
database error; FastAPI only with `serve`."""

from __future__ import annotations

import subprocess
import sys

import pytest

LOADED = "import sys, app.cli; print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))"


@pytest.fixture(scope="module")
def loaded() -> set[str]:
    """The top-level packages a fresh process holds once it has imported the command line."""
    run = subprocess.run([sys.executable, "-c", LOADED], capture_output=True, text=True, check=True)
    return set(run.stdout.split())


def test_the_probe_sees_what_the_command_line_reads(loaded: set[str]) -> None:
    assert {"app", "sqlalchemy", "pydantic"} <= loaded


@pytest.mark.parametrize("package", ["fastapi", "alembic", "uvicorn", "jinja2"])
def test_the_command_line_starts_without_the_web_framework_or_alembic(loaded: set[str], package: str) -> None:
    assert package not in loaded, f"importing app.cli reads {package}"
