"""A non-editable install (as the Dockerfile makes) carries the templates, static files and migrations."""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_wheel_holds_templates_static_files_and_every_migration(tmp_path: Path) -> None:
    # Build from a copy of the tracked files, so the checkout gets no build/ or egg-info.
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, check=True, capture_output=True, text=True)
    source = tmp_path / "source"
    for name in tracked.stdout.splitlines():
        if (ROOT / name).is_file():
            (source / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, source / name)
    built = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(source)],
        check=False,
        capture_output=True,
        text=True,
    )
    assert built.returncode == 0, built.stderr[-2000:]
    (wheel,) = tmp_path.glob("trikecert-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    templates = {p.relative_to(source).as_posix() for p in (source / "templates").rglob("*.html")}
    migrations = {p.relative_to(source).as_posix() for p in (source / "migrations/versions").glob("*.py")}
    assert templates, "no templates found in the checkout"
    assert templates <= names, sorted(templates - names)
    assert migrations <= names, sorted(migrations - names)
    assert "app/web/static/app.css" in names
    assert "migrations/script.py.mako" in names
