"""What a newcomer meets first: the command's version, and a clean `git status` after running the service."""

from __future__ import annotations

import io
import logging
import subprocess
import sys
import time
from pathlib import Path

import pytest

from app import __version__
from app.ops.requests import configure_logging

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


def test_the_log_thread_writes_to_the_standard_error_of_the_moment_not_a_closed_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    first = io.StringIO()
    monkeypatch.setattr(sys, "stderr", first)
    configure_logging()  # as create_app does, while a test's capture is standard error
    first.close()  # that test is over: its capture is closed
    now = io.StringIO()
    monkeypatch.setattr(sys, "stderr", now)
    logging.getLogger("trikecert.access").info("written after the first stream closed")
    deadline = time.monotonic() + 10
    while "written after" not in now.getvalue() and time.monotonic() < deadline:
        time.sleep(0.01)
    assert "written after the first stream closed" in now.getvalue()
    assert "Logging error" not in now.getvalue()
