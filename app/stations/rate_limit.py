"""Per-station-key rate limit: a fixed-window counter row per station, bumped by one atomic upsert.

The counter lives in the database, so every worker process shares it. One statement per request
(INSERT ... ON CONFLICT DO UPDATE ... RETURNING, on SQLite and PostgreSQL alike) opens a new window,
or counts the request in the current one, and reads the count back. On PostgreSQL it runs in
autocommit on its own connection (the row lock lasts one statement), joined in the same statement
with the look-up of the station key, so authenticating and counting a request take one round trip;
on SQLite it takes the writer's turn (app.db.begin_write) for that statement and its commit.
"""

from __future__ import annotations

import time
from functools import cache
from typing import Any

from sqlalchemy import BigInteger, Engine, String, bindparam, case, literal, select
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import Session, make_transient_to_detached

from app.api.errors import ErrorOut
from app.api.windows import RateLimit, seconds_left, window_start
from app.db import begin_write
from app.errors import ServiceError
from app.stations.models import Station, StationRateWindow
from app.stations.service import authenticate_station, hash_key

RATE_LIMIT_RULE = "rate_limit"


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


def on_conflict_count(statement: Any, *returning: Any) -> Any:
    """Open a new window, or count this request in the current one; return the count and window
    (after any `returning` columns)."""
    row = StationRateWindow
    current = row.window_start >= statement.excluded.window_start  # a late request counts in the newer one
    return statement.on_conflict_do_update(
        index_elements=[row.station_id],
        set_={
            "request_count": case((current, row.request_count + 1), else_=1),
            "window_start": case((current, row.window_start), else_=statement.excluded.window_start),
        },
    ).returning(*returning, row.request_count, row.window_start)


def _upsert(session: Session, station_id: int, window_start: int) -> Any:
    """The one statement: open a new window or count this request in the current one."""
    dialect = session.get_bind().dialect.name
    insert = postgresql.insert if dialect == "postgresql" else sqlite.insert
    values = {"station_id": station_id, "window_start": window_start, "request_count": 1}
    return on_conflict_count(insert(StationRateWindow).values(**values))


def check_count(limit: RateLimit, count: int, started: int, now: float) -> None:
    """RateLimited (429, with Retry-After) when `count` requests in the window opened at `started`
    are over the limit."""
    if count > limit.limit:
        raise RateLimited(limit, seconds_left(limit, started, now))


def _count_in_session(session: Session, *, station_id: int, limit: RateLimit, now: float) -> None:
    """Count one request of this station in the session's own transaction and commit; RateLimited
    when it is over the limit. SQLite takes the writer's turn for the statement and its commit."""
    begin_write(session)
    count, started = session.execute(_upsert(session, station_id, window_start(limit, now))).one()
    session.commit()
    check_count(limit, count, started, now)


@cache
def _authenticate_and_count_statement() -> Any:
    """PostgreSQL: the active station holding the key, and its request counted, in one statement.

    Built once (parameters `key_hash` and `window_start`): constructing it is a good part of its cost.
    """
    key_hash = bindparam("key_hash", type_=String)
    station = select(Station.__table__).where(Station.key_hash == key_hash, Station.active).cte("station")
    counted = on_conflict_count(
        postgresql.insert(StationRateWindow).from_select(
            ["station_id", "window_start", "request_count"],
            select(station.c.id, bindparam("window_start", type_=BigInteger), literal(1)),
        ),
        StationRateWindow.station_id,
    ).cte("counted")
    return select(station, counted.c.request_count, counted.c.window_start).join_from(
        station, counted, station.c.id == counted.c.station_id
    )


def authenticate_and_count(
    session: Session, key: str, *, limit: RateLimit, now: float | None = None
) -> Station | None:
    """The active station holding this key (or None), its request counted; RateLimited beyond the limit.

    The station joins the session as a persistent object, as if loaded by it.
    """
    now = time.time() if now is None else now
    bind = session.get_bind()
    if limit.limit <= 0 or bind.dialect.name != "postgresql" or not isinstance(bind, Engine):
        station = authenticate_station(session, key)
        if station is not None and limit.limit > 0:
            _count_in_session(session, station_id=station.id, limit=limit, now=now)
        return station
    # Every request of a station bumps the same row: the statement runs in autocommit on its own
    # connection, so the row lock is held only while the server runs it, never across a round trip
    # or a Python thread waiting for the GIL; it is returned before the session takes one.
    parameters = {"key_hash": hash_key(key), "window_start": window_start(limit, now)}
    with bind.connect().execution_options(isolation_level="AUTOCOMMIT") as connection:
        row = connection.execute(_authenticate_and_count_statement(), parameters).mappings().one_or_none()
    if row is None:
        return None
    found = Station(**{column.key: row[column.name] for column in Station.__table__.columns})
    make_transient_to_detached(found)
    station = session.merge(found, load=False)  # the session's own instance if it already has one
    check_count(limit, row["request_count"], row["window_start"], now)
    return station


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
