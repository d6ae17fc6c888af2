"""The mark reads' kept SQLite connection (app/marks.py KeptReader): every read sees the newest commit,
a file moved or replaced is opened afresh, a file that has gone is never made anew, and it cannot write."""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from pathlib import Path

import pytest

from app.marks import KeptReader

MARK = "SELECT (SELECT max(id) FROM event), (SELECT count(*) FROM event)"


def _database(path: Path, events: int) -> None:
    """A WAL database like the service's, with `events` rows, every connection to it closed."""
    with sqlite3.connect(path) as connection:
        connection.execute("PRAGMA journal_mode=WAL")
        connection.execute("CREATE TABLE event (id INTEGER PRIMARY KEY)")
        connection.executemany("INSERT INTO event DEFAULT VALUES", [()] * events)
    connection.close()


@pytest.fixture
def reader(tmp_path: Path) -> Iterator[KeptReader]:
    _database(tmp_path / "records.db", 2)
    kept = KeptReader(str(tmp_path / "records.db"))
    yield kept
    kept.close()


def test_every_read_sees_the_newest_commit(reader: KeptReader, tmp_path: Path) -> None:
    assert reader.read(MARK) == (2, 2)
    writer = sqlite3.connect(tmp_path / "records.db")
    writer.execute("INSERT INTO event DEFAULT VALUES")
    assert reader.read(MARK) == (2, 2), "not committed yet"
    writer.commit()
    assert reader.read(MARK) == (3, 3)
    writer.execute("DELETE FROM event WHERE id = 1")
    writer.commit()
    writer.close()
    assert reader.read(MARK) == (3, 2)


def test_a_replaced_file_is_read_afresh_and_a_gone_one_is_not_made_anew(
    reader: KeptReader, tmp_path: Path
) -> None:
    path = tmp_path / "records.db"
    assert reader.read(MARK) == (2, 2)
    path.rename(tmp_path / "away.db")
    with pytest.raises(sqlite3.OperationalError, match=r"records\.db is missing"):
        reader.read(MARK)
    assert not path.exists()
    _database(tmp_path / "restored.db", 5)
    (tmp_path / "restored.db").rename(path)
    assert reader.read(MARK) == (5, 5)
    (tmp_path / "away.db").rename(path)  # the first file back, in place of the other
    assert reader.read(MARK) == (2, 2)


def test_it_cannot_write(reader: KeptReader) -> None:
    with pytest.raises(sqlite3.OperationalError, match="readonly"):
        reader.read("INSERT INTO event DEFAULT VALUES")
    assert reader.read(MARK) == (2, 2)
