"""Engine, sessions and the declarative base with a constraint naming convention."""

from __future__ import annotations

import fcntl
import os
import select
import sqlite3
import threading
from collections.abc import AsyncIterator
from datetime import UTC, datetime
from functools import lru_cache
from typing import Any

from sqlalchemy import (
    BigInteger,
    ColumnElement,
    Connection,
    DateTime,
    Engine,
    Integer,
    MetaData,
    cast,
    create_engine,
    event,
    exc,
    func,
    make_url,
)
from sqlalchemy.orm import DeclarativeBase, Session, sessionmaker
from sqlalchemy.types import TypeDecorator
from starlette.concurrency import run_in_threadpool
from starlette.requests import Request

from app.config import get_settings

NAMING_CONVENTION = {
    "ix": "ix_%(column_0_label)s",
    "uq": "uq_%(table_name)s_%(column_0_N_name)s",
    "ck": "ck_%(table_name)s_%(constraint_name)s",
    "fk": "fk_%(table_name)s_%(column_0_name)s_%(referred_table_name)s",
    "pk": "pk_%(table_name)s",
}


class Base(DeclarativeBase):
    """Base of every ORM model."""

    metadata = MetaData(naming_convention=NAMING_CONVENTION)


class UTCDateTime(TypeDecorator[datetime]):
    """A timezone-aware UTC datetime on every backend (SQLite stores naive values)."""

    impl = DateTime(timezone=True)
    cache_ok = True

    def process_bind_param(self, value: datetime | None, dialect: Any) -> datetime | None:
        """Refuse naive datetimes and store UTC."""
        if value is None:
            return None
        if value.tzinfo is None:
            raise ValueError("naive datetime: store timezone-aware UTC values only")
        return value.astimezone(UTC)

    def process_result_value(self, value: datetime | None, dialect: Any) -> datetime | None:
        """Give back an aware UTC datetime."""
        if value is None:
            return None
        return value.replace(tzinfo=UTC) if value.tzinfo is None else value.astimezone(UTC)


def epoch_seconds(dialect: str, moment: ColumnElement[datetime] | Any) -> ColumnElement[int]:
    """A stored time stamp as whole seconds since 1970 (UTC, rounded down), worked out in SQL by the
    database of `dialect` (its name: postgresql or sqlite)."""
    if dialect == "postgresql":
        return cast(func.floor(func.extract("epoch", moment)), BigInteger)
    # SQLite keeps UTC as text; strftime('%s') reads it as seconds since 1970.
    return cast(func.strftime("%s", moment), Integer)


def utcnow() -> datetime:
    """The current time, timezone-aware, in UTC."""
    return datetime.now(UTC)


WRITE_OPTION = "trikecert_write"
SQLITE_BUSY_SECONDS = 30


def begin_write(session: Session) -> None:
    """Start the session's next transaction as a write transaction.

    On SQLite that is `BEGIN IMMEDIATE`, taken behind the process's writer lock: writers queue in
    order and wake as soon as the writer before them commits, instead of starting deferred, reading,
    then failing or sleeping in SQLite's busy handler when they try to write. Reads done so far in
    the session ran outside any SQLite transaction (the driver begins one only before a write), so a
    transaction that has not written yet is committed first, keeping those reads out of the writer's
    turn. Elsewhere, and once the transaction has written, it does nothing.
    """
    if session.get_bind().dialect.name != "sqlite":
        return
    if session.in_transaction():
        if session.new or session.dirty or session.deleted:
            return
        if session.connection().connection.dbapi_connection.in_transaction:  # type: ignore[union-attr]
            return  # it has written (or holds the writer's turn): stay in it
        session.commit()
    session.connection(execution_options={WRITE_OPTION: True})


def autocommit(connection: Connection) -> Connection:
    """PostgreSQL: run each statement as a transaction of its own (a submission's look-up and its
    one-statement write); SQLite keeps the driver's handling (reads outside a transaction)."""
    if connection.dialect.name == "postgresql":
        connection.execution_options(isolation_level="AUTOCOMMIT")
    return connection


def begin_connection_write(connection: Connection) -> None:
    """SQLite: start the write transaction (`BEGIN IMMEDIATE` behind the writer lock) unless this
    connection is in one already; reads done so far are committed first, keeping them out of the
    writer's turn. PostgreSQL: nothing (in autocommit each statement is a transaction of its own)."""
    if connection.dialect.name != "sqlite":
        return
    if connection.in_transaction():
        if connection.connection.dbapi_connection.in_transaction:  # type: ignore[union-attr]
            return  # it has written, or holds the writer's turn: stay in it
        connection.commit()
    connection.execution_options(**{WRITE_OPTION: True})
    connection.begin()
    connection.execution_options(**{WRITE_OPTION: False})  # this transaction only; later reads stay apart


class _WriterLock:
    """One writer at a time: a lock among this process's threads, then an flock(2) on a file beside
    the database among processes (uvicorn workers), so a waiting writer wakes as soon as the one
    before it commits instead of polling in SQLite's busy handler."""

    def __init__(self, database: str | None) -> None:
        self.threads = threading.Lock()
        self.path = f"{database}-writer.lock" if database and database != ":memory:" else None
        self.file: int | None = None

    def acquire(self) -> None:
        if not self.threads.acquire(timeout=SQLITE_BUSY_SECONDS):  # busy, not broken: a 503, try again
            raise exc.TimeoutError("SQLite: waited too long for this process's writer lock")
        if self.path is None:
            return
        try:
            if self.file is None:
                self.file = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o600)
            fcntl.flock(self.file, fcntl.LOCK_EX)
        except BaseException:
            self.threads.release()
            raise

    def release(self) -> None:
        try:
            if self.file is not None:
                fcntl.flock(self.file, fcntl.LOCK_UN)
        finally:
            self.threads.release()


def _single_writer(engine: Engine) -> None:
    """SQLite: a write transaction starts with BEGIN IMMEDIATE behind the writer lock."""
    writer = _WriterLock(engine.url.database)
    holders: set[int] = set()  # ids of the DBAPI connections holding `writer`

    # Other transactions keep the driver's own handling: reads outside a transaction, a deferred
    # BEGIN before the first write.
    @event.listens_for(engine, "begin")
    def _begin(connection: Any) -> None:
        if not connection.get_execution_options().get(WRITE_OPTION):
            return
        dbapi_connection = connection.connection.dbapi_connection
        writer.acquire()
        holders.add(id(dbapi_connection))
        try:
            connection.exec_driver_sql("BEGIN IMMEDIATE")  # other processes: the busy timeout
        except BaseException:
            _release(dbapi_connection)
            raise

    def _release(dbapi_connection: Any) -> None:
        raw = getattr(dbapi_connection, "dbapi_connection", dbapi_connection)  # the pool's proxy or not
        if id(raw) in holders:
            holders.discard(id(raw))
            writer.release()

    dialect = engine.dialect
    commit, rollback, close = dialect.do_commit, dialect.do_rollback, dialect.do_close

    def do_commit(dbapi_connection: Any) -> None:
        try:
            commit(dbapi_connection)
        finally:
            _release(dbapi_connection)

    def do_rollback(dbapi_connection: Any) -> None:
        try:
            rollback(dbapi_connection)
        finally:
            _release(dbapi_connection)

    def do_close(dbapi_connection: Any) -> None:  # a connection discarded mid-transaction
        try:
            close(dbapi_connection)
        finally:
            _release(dbapi_connection)

    setattr(dialect, "do_commit", do_commit)  # noqa: B010  (this engine's dialect instance only)
    setattr(dialect, "do_rollback", do_rollback)  # noqa: B010
    setattr(dialect, "do_close", do_close)  # noqa: B010


# How long a client should wait before trying again when the database does not answer.
RETRY_AFTER_SECONDS = 5
_UNAVAILABLE = (exc.OperationalError, exc.InterfaceError, exc.TimeoutError, exc.DisconnectionError)


def is_outage(error: BaseException) -> bool:
    """Did the database fail to answer (down, unreachable, locked, out of connections), not the query?

    These pass: a request sent again once the database is back can succeed. Every other database
    error (a broken constraint, bad SQL) is a fault of the request or the code, not of availability.
    """
    if isinstance(error, _UNAVAILABLE):
        return True
    return isinstance(error, exc.DBAPIError) and error.connection_invalidated


def file_identity(path: str) -> tuple[int, int] | None:
    """The file at the path as (device, inode), or None when there is none."""
    try:
        status = os.stat(path)
    except OSError:
        return None
    return status.st_dev, status.st_ino


def _same_file_every_checkout(engine: Engine, path: str) -> None:
    """SQLite: a pooled connection is used only while its file is still the one at the path.

    A connection keeps the file it opened even after that file is moved, replaced or removed; it would
    go on answering, and storing, in a file nobody will read again. Such a connection is discarded at
    checkout instead, and a file that has gone is not created afresh (empty) in its place: the app
    answers "unavailable" until the database is back, then reconnects by itself.
    """
    opened = threading.Event()

    @event.listens_for(engine, "do_connect")
    def _no_new_file(_dialect: Any, _record: Any, _cargs: Any, _cparams: Any) -> None:
        if opened.is_set() and file_identity(path) is None:
            raise sqlite3.OperationalError(f"unable to open database file: {path} is missing")

    @event.listens_for(engine, "connect")
    def _remember(_dbapi_connection: Any, record: Any) -> None:
        record.info["file"] = file_identity(path)
        opened.set()

    @event.listens_for(engine, "checkout")
    def _check(_dbapi_connection: Any, record: Any, _proxy: Any) -> None:
        if file_identity(path) != record.info.get("file"):
            raise exc.DisconnectionError(f"the database file {path} was moved, replaced or removed")


def make_engine(url: str, *, autocommit: bool = False) -> Engine:
    """An engine for the URL; SQLite gets WAL, foreign keys, a busy timeout and a single-writer path.
    `autocommit`: PostgreSQL runs each statement as its own transaction (one round trip for a read)."""
    if url.startswith("sqlite"):
        settings = get_settings()
        in_memory = make_url(url).database in (None, "", ":memory:")
        pool = (
            {}
            if in_memory
            else {"pool_size": settings.db_pool_size, "max_overflow": settings.db_max_overflow}
        )
        engine = create_engine(
            url, connect_args={"check_same_thread": False, "timeout": SQLITE_BUSY_SECONDS}, **pool
        )

        @event.listens_for(engine, "connect")
        def _sqlite_pragmas(dbapi_connection: Any, _record: Any) -> None:
            cursor = dbapi_connection.cursor()
            cursor.execute("PRAGMA foreign_keys=ON")
            cursor.execute("PRAGMA journal_mode=WAL")
            cursor.execute("PRAGMA synchronous=FULL")
            cursor.execute(f"PRAGMA busy_timeout={SQLITE_BUSY_SECONDS * 1000}")
            cursor.close()

        _single_writer(engine)
        if not in_memory and not make_url(url).query.get("uri"):
            _same_file_every_checkout(engine, str(make_url(url).database))
        return engine
    settings = get_settings()
    isolation = {"isolation_level": "AUTOCOMMIT"} if autocommit else {}
    engine = create_engine(
        url, pool_size=settings.db_pool_size, max_overflow=settings.db_max_overflow, **isolation
    )
    _still_open_at_checkout(engine)
    return engine


def _still_open_at_checkout(engine: Engine) -> None:
    """PostgreSQL: a pooled connection the server has closed is replaced at checkout, at no round trip.

    An idle connection has nothing to read; once the server closes it (a restart, an administrator's
    terminate) its socket turns readable, with the server's goodbye or the end of the stream. A
    socket readable at checkout is discarded and a new connection made in its place (SQLAlchemy
    retries the checkout). `pool_pre_ping` would learn the same with a SELECT per request.
    """

    @event.listens_for(engine, "checkout")
    def _check(dbapi_connection: Any, _record: Any, _proxy: Any) -> None:
        if dbapi_connection.closed or _readable(dbapi_connection.fileno()):
            raise exc.DisconnectionError("the database closed this pooled connection")


def _readable(fileno: int) -> bool:
    poller = select.poll()
    poller.register(fileno, select.POLLIN | select.POLLERR | select.POLLHUP)
    return bool(poller.poll(0))


@lru_cache
def get_engine() -> Engine:
    """The process-wide engine for the configured database."""
    return make_engine(get_settings().database_url)


@lru_cache
def get_sessionmaker() -> sessionmaker[Session]:
    """The process-wide session factory."""
    return sessionmaker(bind=get_engine(), expire_on_commit=False)


REQUEST_ORIGIN_KEY = "trikecert_request_origin"


async def get_session(request: Request) -> AsyncIterator[Session]:
    """A FastAPI dependency: one session per request, closed afterwards; it carries the request's
    client address and id, for the audit log.

    Async, so that opening it costs no trip through the thread pool (a new session touches no
    database); closing goes to the pool only when a transaction is still open (its rollback is I/O).
    """
    session = get_sessionmaker()()
    session.info[REQUEST_ORIGIN_KEY] = (
        request.client.host if request.client else None,
        getattr(request.state, "request_id", None),
    )
    try:
        yield session
    finally:
        if session.in_transaction():
            await run_in_threadpool(session.close)
        else:
            session.close()
