"""Production refuses to start without the public https address printed on every certificate and
QR code; development and tests keep their local default."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from pydantic import ValidationError

from app.config import Settings

BIN = Path(sys.executable).parent


def start_in_production(tmp_path: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """`trikecert serve` as production with these settings, in an empty folder (no .env)."""
    environment = {k: v for k, v in os.environ.items() if not k.startswith("TRIKECERT_")}
    environment.update(
        TRIKECERT_ENVIRONMENT="production",
        TRIKECERT_DATABASE_URL=f"sqlite:///{tmp_path / 'trikecert.db'}",
        **env,
    )
    return subprocess.run(
        [BIN / "trikecert", "serve", "--port", "1"],
        env=environment,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


@pytest.mark.parametrize(
    ("env", "says"),
    [
        ({}, "TRIKECERT_BASE_URL is not set"),
        ({"TRIKECERT_BASE_URL": "http://trikecert.example.gov"}, "is not an https address"),
        ({"TRIKECERT_BASE_URL": "https://"}, "is not an https address"),
        ({"TRIKECERT_BASE_URL": "trikecert.example.gov"}, "is not an https address"),
    ],
    ids=["unset", "http", "no-host", "no-scheme"],
)
def test_production_without_a_public_https_address_refuses_to_start_with_a_message(
    tmp_path: Path, env: dict[str, str], says: str
) -> None:
    started = start_in_production(tmp_path, **env)

    assert started.returncode == 2
    assert started.stderr.startswith("trikecert: refusing to start: TRIKECERT_BASE_URL")
    assert says in started.stderr
    assert "https://trikecert.example.gov" in started.stderr  # the message shows what to set
    assert "Traceback" not in started.stderr
    assert not (tmp_path / "trikecert.db").exists()  # refused before touching anything


def test_production_refuses_a_placeholder_app_role_password_at_start(tmp_path: Path) -> None:
    started = start_in_production(
        tmp_path, TRIKECERT_BASE_URL="https://trikecert.example.gov", TRIKECERT_APP_DB_PASSWORD="changeme"
    )

    assert started.returncode == 2
    assert "TRIKECERT_APP_DB_PASSWORD" in started.stderr
    assert "Traceback" not in started.stderr


def test_production_accepts_an_https_address_and_development_keeps_the_local_default() -> None:
    public = Settings(environment="production", base_url="https://trikecert.example.gov/")
    assert public.base_url == "https://trikecert.example.gov/"
    assert Settings(environment="development").base_url == "http://127.0.0.1:8000"
    assert Settings(environment="test", base_url="http://testserver").base_url == "http://testserver"


def test_the_app_role_must_be_a_plain_identifier() -> None:
    with pytest.raises(ValidationError, match="lower-case letters, digits and _"):
        Settings(app_db_role='app"; DROP TABLE inspection; --')
    assert Settings(app_db_role="trikecert_app").app_db_role == "trikecert_app"
