"""What a newcomer meets first: the command's version, and a clean `git status` after running the service."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from app import __version__

ROOT = Path(__file__).resolve().parents[2]


def test_trikecert_version_prints_the_installed_version() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "app.cli", "--version"], capture_output=True, text=True, check=False, cwd=ROOT
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == f"trikecert {__version__}"
    assert __version__ != "0+unknown"
    assert __version__[0].isdigit()


def test_files_the_service_leaves_beside_its_sqlite_database_are_ignored_by_git() -> None:
    names = [
        "trikecert.db",
        "trikecert.db-wal",
        "trikecert.db-shm",
        "trikecert.db-writer.lock",
        "trikecert-signing-key.pem",  # the signing key, made on first use beside the database
    ]
    done = subprocess.run(
        ["git", "check-ignore", "--no-index", *names], capture_output=True, text=True, check=False, cwd=ROOT
    )
    assert done.stdout.split() == names
