"""A command meeting a database it cannot use says what to do, in one line, and exits 2: never a
traceback for an operator who has not migrated yet or whose server is down."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from app import config, db
from app.cli import main


@pytest.fixture
def database_at(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Iterator[None]:
    """Commands run against the URL set in TRIKECERT_DATABASE_URL by the test (caches cleared)."""
    monkeypatch.setenv("TRIKECERT_SIGNING_KEY_FILE", str(tmp_path / "signing-key.pem"))
    _forget_settings_and_engines()
    yield
    db.get_engine().dispose()
    monkeypatch.undo()
    _forget_settings_and_engines()


def _forget_settings_and_engines() -> None:
    config.get_settings.cache_clear()
    db.get_engine.cache_clear()
    db.get_sessionmaker.cache_clear()


COMMANDS = [
    ["revoke-certificate", "TRK-2026-000001-E", "--reason", "plate forged"],
    ["signing-keys"],
    ["trust-bundle", "--out", "bundle.jws"],
]


@pytest.mark.parametrize("command", COMMANDS, ids=lambda command: command[0])
def test_an_unmigrated_database_says_run_migrate(
    command: list[str],
    database_at: None,
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.setenv("TRIKECERT_DATABASE_URL", f"sqlite:///{tmp_path / 'new.db'}")
    monkeypatch.chdir(tmp_path)
    assert main(command) == 2
    out, err = capsys.readouterr()
    assert err == "trikecert: the database is not migrated to this version: run `trikecert migrate` first\n"
    assert "Traceback" not in out + err


def test_a_server_that_does_not_answer_is_named_as_such(
    database_at: None, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("TRIKECERT_DATABASE_URL", "postgresql+psycopg://postgres@127.0.0.1:9/nothing")
    assert main(["signing-keys"]) == 2
    _out, err = capsys.readouterr()
    assert err.startswith("trikecert: the database did not answer (")
    assert err.endswith("); check that it runs, then try again\n")
    assert err.count("\n") == 1
