"""Change marks: one small read of a few index look-ups that says whether records changed, the check a
kept answer passes on every request before it is served again (answer_cache, the trust bundle).

The statement is compiled once per database and run on a pooled DBAPI connection, without a session or
the ORM's result processing: a mark is only ever compared with a mark read the same way. On SQLite the
read runs in the event loop (a WAL read of a local file never waits for a writer, and a trip through
the thread pool cost several times the read), on a read-only connection kept open for it (KeptReader),
or, while another thread's loop reads on that one, on an engine of the event loops' own: the requests'
pool may be taken by routes whose sessions close in the loop, which must not wait for them. On
PostgreSQL the read goes through the thread pool, so a database that stalls stalls no other request,
on an engine of its own in autocommit: one round trip, no BEGIN and COMMIT around it.
"""

from __future__ import annotations

import sqlite3
import threading
from functools import lru_cache
from pathlib import Path
from typing import Any

from anyio.to_thread import run_sync
from sqlalchemy import Engine, Select
from sqlalchemy.engine import make_url

from app.config import get_settings
from app.db import SQLITE_BUSY_SECONDS, file_identity, get_engine, make_engine

Mark = tuple[object, ...]


class MarkQuery:
    """A statement that reads a change mark, compiled once per database."""

    def __init__(self, statement: Select[Any]) -> None:
        self.statement = statement
        self._sql: dict[str, str] = {}
        self._sqlite_sql: str | None = None  # the same on every SQLite file: one driver per process

    def _sql_for(self, key: str, dialect: Any) -> str:
        sql = self._sql.get(key)
        if sql is None:
            # Constants only (no parameters), so the text runs as it is on any driver.
            sql = str(self.statement.compile(dialect=dialect, compile_kwargs={"literal_binds": True}))
            self._sql[key] = sql
        return sql

    def read(self, engine: Engine | None = None) -> Mark:
        """The mark now (blocking), on the marks' engine unless another is given."""
        engine = engine or _marks_engine(get_settings().database_url)
        sql = self._sql_for(str(engine.url), engine.dialect)
        connection = engine.raw_connection()
        try:
            cursor = connection.cursor()
            try:
                cursor.execute(sql)
                row = cursor.fetchone()
            finally:
                cursor.close()
            connection.commit()  # end the read's transaction where the driver began one
        finally:
            connection.close()
        return tuple(row) if row is not None else ()

    async def read_soon(self) -> Mark:
        """The mark now, from async code: in the event loop on SQLite, else in the thread pool."""
        url = get_settings().database_url
        if not url.startswith("sqlite"):
            return await run_sync(self.read)
        path = _plain_file(url)
        if path is None:  # in memory (one per engine: the requests' own), or a URI's options
            return self.read(None if _in_memory(url) else _event_loop_engine(url))
        if self._sqlite_sql is None:
            self._sqlite_sql = self._sql_for(url, _event_loop_engine(url).dialect)
        mark = _kept_reader(path).read(self._sqlite_sql)
        return self.read(_event_loop_engine(url)) if mark is None else mark


@lru_cache(maxsize=8)
def _in_memory(url: str) -> bool:
    return make_url(url).database in (None, "", ":memory:")


@lru_cache(maxsize=8)
def _plain_file(url: str) -> str | None:
    """The path of a SQLite database in a file named plainly (no URI options), else None (in memory,
    or opened as a URI). Parsed once: parsing the URL at every request cost a kept answer an eighth of
    its time."""
    parsed = make_url(url)
    if parsed.database in (None, "", ":memory:") or parsed.query:
        return None
    return str(parsed.database)


class KeptReader:
    """SQLite: one read-only connection to a database file, kept open for the event loops' mark reads.

    A pooled connection's checkout and return cost twice the read itself. The file is still checked
    at every read, as the pool checks it at every checkout (app/db.py): a file moved or replaced is
    opened afresh, and a file that has gone is never created (read-only), so the read fails and the
    route answers as it does when the database is away.
    """

    def __init__(self, path: str) -> None:
        self.path = path
        self._lock = threading.Lock()
        self._connection: sqlite3.Connection | None = None
        self._file: tuple[int, int] | None = None
        self._marks: dict[str, tuple[int, Mark]] = {}  # statement -> (data_version, mark) last read

    def read(self, sql: str) -> Mark | None:
        """The mark now, or None when another thread is reading on this connection at this moment."""
        if not self._lock.acquire(blocking=False):
            return None
        try:
            try:
                return self._read(self._connected(), sql)
            except BaseException:
                self.close()
                raise
        finally:
            self._lock.release()

    def _read(self, connection: sqlite3.Connection, sql: str) -> Mark:
        # data_version changes whenever another connection (of any process) commits to the file, and
        # costs less than the mark's look-ups: while it stays, the mark read last time is the mark now.
        # Read first, so a commit landing between the two is only ever read again, never missed.
        # fetchall() everywhere: the statement ends, and its read with it.
        version = connection.execute("PRAGMA data_version").fetchall()[0][0]
        kept = self._marks.get(sql)
        if kept is not None and kept[0] == version:
            return kept[1]
        rows = connection.execute(sql).fetchall()
        mark = tuple(rows[0]) if rows else ()
        self._marks[sql] = (version, mark)
        return mark

    def _connected(self) -> sqlite3.Connection:
        identity = file_identity(self.path)
        if self._connection is not None and identity == self._file:
            return self._connection
        self.close()
        if identity is None:
            raise sqlite3.OperationalError(f"unable to open database file: {self.path} is missing")
        uri = f"{Path(self.path).absolute().as_uri()}?mode=ro"
        self._connection = sqlite3.connect(
            uri, uri=True, timeout=SQLITE_BUSY_SECONDS, check_same_thread=False
        )
        self._file = identity
        return self._connection

    def close(self) -> None:
        """Close the connection (the next read opens the file again)."""
        self._marks = {}
        if self._connection is not None:
            self._connection.close()
            self._connection = None

    def __del__(self) -> None:
        self.close()


@lru_cache(maxsize=8)
def _kept_reader(path: str) -> KeptReader:
    return KeptReader(path)


@lru_cache(maxsize=8)
def _event_loop_engine(url: str) -> Engine:
    """SQLite: the engine the event loops read marks on (a loop reads one at a time, never waiting)."""
    return make_engine(url)


def _marks_engine(url: str) -> Engine:
    """The engine a blocking read uses: the requests' own on SQLite, else one in autocommit."""
    return get_engine() if url.startswith("sqlite") else _autocommit_engine(url)


@lru_cache(maxsize=8)
def _autocommit_engine(url: str) -> Engine:
    return make_engine(url, autocommit=True)
