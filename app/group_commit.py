"""Group commit on SQLite: the writes that wait for the writer's turn together commit together.

SQLite has one writer at a time, and each durable commit (WAL with `synchronous=FULL`) waits for
an fsync. When many submissions arrive at once, each waiting its turn to write 17 rows and sync,
the turns, not the work, limit the rate. Here the first writer in a process to find no turn being
taken becomes the leader: it takes the writer's turn (app/db.py, `begin_connection_write`), then
writes every write queued in the process by then, its own included, in that one transaction, and
commits once. Each request still answers only after the commit that holds its rows, so nothing is
acknowledged before it is durable.

A batch is all or nothing in SQLite; so when one write fails (a key stored meanwhile by a
concurrent duplicate, say), the batch is rolled back and each of its writes is run again alone, in
a transaction of its own: the others are stored, and the one that failed gets its own error.

PostgreSQL needs none of this (many writers at once, and the submission's write is one statement
in autocommit): there the write runs on the request's connection and is committed at once.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable
from typing import TypeVar, cast

from sqlalchemy import Connection, Engine

from app.db import begin_connection_write

T = TypeVar("T")
Write = Callable[[Connection], T]


class _Queued:
    """One write waiting for its batch, and what came of it."""

    def __init__(self, write: Write[object]) -> None:
        self.write = write
        self.done = False
        self.value: object = None
        self.error: BaseException | None = None

    def outcome(self) -> object:
        if self.error is not None:
            raise self.error
        return self.value


class CommitGroup:
    """The writes of one engine's process, committed in batches (SQLite)."""

    def __init__(self) -> None:
        self._state = threading.Condition()
        self._queue: list[_Queued] = []
        self._leading = False

    @property
    def waiting(self) -> int:
        """How many writes wait for the next batch."""
        with self._state:
            return len(self._queue)

    def write(self, connection: Connection, write: Write[T]) -> T:
        """Run `write` in a write transaction, with any others waiting in this process, and commit;
        its result, or its own error."""
        queued = _Queued(write)
        with self._state:
            self._queue.append(queued)
            while self._leading and not queued.done:
                self._state.wait()
            if queued.done:  # written by the leader before us
                return cast(T, queued.outcome())
            self._leading = True
        try:
            self._lead(connection, queued)
        finally:
            with self._state:
                self._leading = False
                self._state.notify_all()
        return cast(T, queued.outcome())

    def _lead(self, connection: Connection, own: _Queued) -> None:
        """Take the writer's turn, then write and commit everything queued by then."""
        try:
            begin_connection_write(connection)
        except BaseException as error:
            with self._state:  # the turn was not had: this write fails, the others try theirs
                self._queue.remove(own)
            own.error, own.done = error, True
            return
        with self._state:
            batch, self._queue = self._queue, []
        try:
            self._write_batch(connection, batch)
        finally:
            # Whatever stopped the leader half-way is the answer of every write it had not done.
            for queued in batch:
                if not queued.done:
                    queued.error = RuntimeError("the batch's writer stopped before this write was committed")
                    queued.done = True

    def _write_batch(self, connection: Connection, batch: list[_Queued]) -> None:
        try:
            values = [queued.write(connection) for queued in batch]
            connection.commit()
        except Exception as error:
            connection.rollback()
            if len(batch) == 1:
                batch[0].error, batch[0].done = error, True
                return
            for queued in batch:  # each again alone: only the failing write gets its error
                self._write_alone(connection, queued)
            return
        for queued, value in zip(batch, values, strict=True):
            queued.value, queued.done = value, True

    @staticmethod
    def _write_alone(connection: Connection, queued: _Queued) -> None:
        try:
            begin_connection_write(connection)
            queued.value = queued.write(connection)
            connection.commit()
        except Exception as error:
            connection.rollback()
            queued.error = error
        queued.done = True


_GROUPS: weakref.WeakKeyDictionary[Engine, CommitGroup] = weakref.WeakKeyDictionary()
_GROUPS_LOCK = threading.Lock()


def commit_group(engine: Engine) -> CommitGroup:
    """The engine's group of writes in this process."""
    with _GROUPS_LOCK:
        return _GROUPS.setdefault(engine, CommitGroup())


def write_and_commit(connection: Connection, write: Write[T]) -> T:
    """Run `write` on a write transaction and commit it: on SQLite together with the other writes
    waiting in this process (one commit), elsewhere on `connection` at once."""
    if connection.dialect.name != "sqlite":
        value = write(connection)
        connection.commit()
        return value
    return commit_group(connection.engine).write(connection, write)
