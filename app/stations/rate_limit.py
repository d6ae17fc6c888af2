"""Per-station-key rate limit: a fixed-window counter row per station, bumped by one atomic upsert.

The counter lives in the database, so every worker process shares it. One statement per request
(INSERT ... ON CONFLICT DO UPDATE ... RETURNING, on SQLite and PostgreSQL alike) opens a new window,
or counts the request in the current one, and reads the count back. On PostgreSQL it runs in
autocommit on its own connection (the row lock lasts one statement); on SQLite it takes the
writer's turn (app.db.begin_write) for that statement and its commit.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from sqlalchemy import Engine, case
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import Session

from app.api.errors import ErrorOut
from app.db import begin_write
from app.errors import ServiceError
from app.stations.models import StationRateWindow

RATE_LIMIT_RULE = "rate_limit"


@dataclass(frozen=True)
class RateLimit:
    """At most `limit` requests per `window_seconds` per station key; a limit of 0 is no limit."""

    limit: int
    window_seconds: int


class RateLimited(ServiceError):
    """The station sent more requests than its limit allows in this window (429, with Retry-After)."""

    status = 429

    def __init__(self, limit: RateLimit, retry_after: int) -> None:
        super().__init__(
            f"Authorization: this station key sent more than {limit.limit} requests in "
            f"{limit.window_seconds} s; retry after {retry_after} s",
            field="Authorization",
            rule=RATE_LIMIT_RULE,
        )
        self.retry_after = retry_after
        self.headers = {"Retry-After": str(retry_after)}


def _upsert(session: Session, station_id: int, window_start: int) -> Any:
    """The one statement: open a new window or count this request in the current one."""
    dialect = session.get_bind().dialect.name
    insert = postgresql.insert if dialect == "postgresql" else sqlite.insert
    row = StationRateWindow
    statement = insert(row).values(station_id=station_id, window_start=window_start, request_count=1)
    current = row.window_start >= statement.excluded.window_start  # a late request counts in the newer one
    return statement.on_conflict_do_update(
        index_elements=[row.station_id],
        set_={
            "request_count": case((current, row.request_count + 1), else_=1),
            "window_start": case((current, row.window_start), else_=statement.excluded.window_start),
        },
    ).returning(row.request_count, row.window_start)


def count_request(session: Session, *, station_id: int, limit: RateLimit, now: float | None = None) -> None:
    """Count one request of this station and commit; RateLimited when it is over the limit."""
    if limit.limit <= 0:
        return
    now = time.time() if now is None else now
    window_start = int(now // limit.window_seconds) * limit.window_seconds
    statement = _upsert(session, station_id, window_start)
    bind = session.get_bind()
    if bind.dialect.name == "postgresql" and isinstance(bind, Engine):
        # Every request of a station bumps the same row: run the upsert as one autocommit statement,
        # so its row lock is held only while the server runs it, never across a round trip or a
        # Python thread waiting for the GIL. The session's read (the key lookup) ends first, so a
        # request never holds two pooled connections.
        session.commit()
        with bind.connect().execution_options(isolation_level="AUTOCOMMIT") as connection:
            count, started = connection.execute(statement).one()
    else:
        begin_write(session)  # SQLite: the writer's turn, for this one statement and its commit
        count, started = session.execute(statement).one()
        session.commit()
    if count > limit.limit:
        retry_after = max(1, math.ceil(started + limit.window_seconds - now))
        raise RateLimited(limit, retry_after)


RATE_LIMITED_RESPONSE: dict[int | str, dict[str, Any]] = {
    429: {
        "model": ErrorOut,
        "description": "Too many requests from this station key in the current window; retry after "
        "`Retry-After` seconds.",
        "headers": {
            "Retry-After": {
                "description": "Seconds until the station key's window reopens.",
                "required": True,
                "schema": {"type": "integer", "minimum": 1},
            }
        },
    }
}
