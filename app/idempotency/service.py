"""Claim, look up, remember and prune idempotency keys; one key per station, kept at least 24 hours.

Concurrency: on PostgreSQL a transaction-scoped advisory lock on (station, key) is taken before the
key is looked up, so a duplicate that arrives while the first request still runs is told 409 at
once. SQLite has a single writer: a duplicate waits for the first to commit, then its own insert of
the key fails and it is answered with the stored response instead.
"""

from __future__ import annotations

import hashlib
import json
import logging
import secrets
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any, cast

from sqlalchemy import Connection, Table, bindparam, delete, func, insert, select

from app.db import begin_connection_write, get_engine, utcnow
from app.errors import Conflict, InvalidInput
from app.idempotency.models import IdempotencyKey
from app.prepared import PreparedCache

logger = logging.getLogger("trikecert.idempotency")
KEY_FIELD = "Idempotency-Key"
PRUNE_ONE_IN = 200  # about one stored key in this many also prunes the expired ones


@dataclass(frozen=True)
class Claim:
    """A station's use of a key for one request: which operation, and a hash of what it asked."""

    station_id: int
    key: str
    operation: str
    request_hash: str


def request_hash(operation: str, payload: Any) -> str:
    """SHA-256 of the operation and the validated body as canonical JSON (key order and spacing ignored)."""
    canonical = json.dumps([operation, payload], sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(canonical.encode()).hexdigest()


class KeyInFlight(Conflict):
    """A request with this key is still being processed (409); retrying later gets its answer."""

    def __init__(self) -> None:
        super().__init__(
            f"{KEY_FIELD}: a request with this key is still being processed; "
            "retry in a moment to get its answer",
            field=KEY_FIELD,
            rule="idempotency_key_in_flight",
        )
        self.headers = {"Retry-After": "1"}


class KeyReused(InvalidInput):
    """The key was already used for a different request (422); a new request needs a new key."""

    def __init__(self, stored: StoredAnswer) -> None:
        super().__init__(
            f"{KEY_FIELD}: this key was already used by this station for a different request "
            f"({stored.operation} at {stored.created_at:%Y-%m-%dT%H:%M:%SZ}); "
            "send a new key with each new request",
            field=KEY_FIELD,
            rule="idempotency_key_reused",
        )


def lock_id(claim: Claim) -> int:
    """The advisory lock of a station's key (PostgreSQL)."""
    digest = hashlib.sha256(f"idempotency-key:{claim.station_id}:{claim.key}".encode()).digest()
    return int.from_bytes(digest[:8], "big", signed=True)


def try_lock(connection: Connection, claim: Claim) -> bool:
    """Hold (station, key) for this transaction: False when another transaction holds it (PostgreSQL only)."""
    if connection.dialect.name != "postgresql":
        return True
    [row] = _TRY_LOCK(connection).execute(connection, {"lock": lock_id(claim)})
    return bool(row["locked"])


_TRY_LOCK = PreparedCache(
    lambda _dialect: select(func.pg_try_advisory_xact_lock(bindparam("lock")).label("locked"))
)


@dataclass(frozen=True)
class StoredAnswer:
    """A key as stored: the request it came with and the answer it got."""

    operation: str
    request_hash: str
    status_code: int
    response_body: str
    created_at: datetime


KEYS_TABLE = _KEYS = cast(Table, IdempotencyKey.__table__)
_THIS_KEY = (_KEYS.c.station_id == bindparam("station_id")) & (_KEYS.c.key == bindparam("key"))
# A stored answer's columns, as StoredAnswer names them.
ANSWER_COLUMNS = ("operation", "request_hash", "status_code", "response_body", "created_at")
_STORED = PreparedCache(lambda _dialect: select(*[_KEYS.c[name] for name in ANSWER_COLUMNS]).where(_THIS_KEY))
_REMEMBER = PreparedCache(
    lambda _dialect: insert(_KEYS).values(
        {
            name: bindparam(name, type_=_KEYS.c[name].type)
            for name in (
                "station_id",
                "key",
                "operation",
                "request_hash",
                "status_code",
                "response_body",
                "created_at",
            )
        }
    )
)


def stored_answer(connection: Connection, claim: Claim, *, retention: timedelta) -> StoredAnswer | None:
    """The answer stored under this station's key, or None; a key older than `retention` is forgotten."""
    where = {"station_id": claim.station_id, "key": claim.key}
    rows = _STORED(connection).execute(connection, where)
    if not rows:
        return None
    return unless_expired(connection, claim, StoredAnswer(**rows[0]), retention=retention)


def unless_expired(
    connection: Connection, claim: Claim, stored: StoredAnswer, *, retention: timedelta
) -> StoredAnswer | None:
    """The stored answer, or None (and the key forgotten) when it is older than `retention`."""
    if stored.created_at >= utcnow() - retention:
        return stored
    connection.execute(delete(_KEYS).where(_THIS_KEY), {"station_id": claim.station_id, "key": claim.key})
    return None


def check_same_request(claim: Claim, stored: StoredAnswer) -> None:
    """KeyReused unless the stored key came with the same operation and body."""
    if stored.operation != claim.operation or stored.request_hash != claim.request_hash:
        raise KeyReused(stored)


def remember(connection: Connection, claim: Claim, *, status_code: int, body: bytes) -> None:
    """Store the key and its answer in the connection's transaction (the caller's commit stores both)."""
    _REMEMBER(connection).execute(
        connection,
        {
            "station_id": claim.station_id,
            "key": claim.key,
            "operation": claim.operation,
            "request_hash": claim.request_hash,
            "status_code": status_code,
            "response_body": body.decode(),
            "created_at": utcnow(),
        },
    )


def prune(connection: Connection, *, older_than: datetime) -> int:
    """Delete the keys stored before `older_than` and commit; how many went."""
    begin_connection_write(connection)
    result = connection.execute(delete(_KEYS).where(_KEYS.c.created_at < older_than))
    connection.commit()
    return int(getattr(result, "rowcount", 0) or 0)


def maybe_prune(*, retention: timedelta) -> None:
    """Now and then (one call in PRUNE_ONE_IN), prune expired keys on a connection of its own; a
    failure is logged, never raised."""
    if secrets.randbelow(PRUNE_ONE_IN):
        return
    try:
        with get_engine().connect() as connection:
            prune(connection, older_than=utcnow() - retention)
    except Exception:  # pruning is housekeeping: the answer was already stored
        logger.exception("pruning expired idempotency keys failed")
