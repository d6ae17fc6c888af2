"""Change marks: one small read of a few index look-ups that says whether records changed, the check a
kept answer passes on every request before it is served again (answer_cache, the trust bundle).

The statement is compiled once per database and run on a pooled DBAPI connection, without a session or
the ORM's result processing: a mark is only ever compared with a mark read the same way. On SQLite the
read runs in the event loop (a WAL read of a local file never waits for a writer, and a trip through
the thread pool cost several times the read), on an engine of the event loops' own: the requests'
pool may be taken by routes whose sessions close in the loop, which must not wait for them. On
PostgreSQL the read goes through the thread pool, so a database that stalls stalls no other request,
on an engine of its own in autocommit: one round trip, no BEGIN and COMMIT around it.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

from anyio.to_thread import run_sync
from sqlalchemy import Engine, Select
from sqlalchemy.engine import make_url

from app.config import get_settings
from app.db import get_engine, make_engine

Mark = tuple[object, ...]


class MarkQuery:
    """A statement that reads a change mark, compiled once per database."""

    def __init__(self, statement: Select[Any]) -> None:
        self.statement = statement
        self._sql: dict[str, str] = {}

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
        return self.read(None if _in_memory(url) else _event_loop_engine(url))


@lru_cache(maxsize=8)
def _in_memory(url: str) -> bool:
    """An in-memory SQLite database (one per engine)? Parsed once: parsing the URL at every request
    cost a kept answer an eighth of its time."""
    return make_url(url).database in (None, "", ":memory:")


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
