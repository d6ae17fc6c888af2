"""The counts of the open days' closed UTC hours, taken once from the records and stored (derived data).

The open days (today, and yesterday during the first hour after midnight) are the only ones the
statistics count from the records; by evening today holds most of a day's inspections. An hour is
closed, like a day, CLOSED_AFTER after it ends: none of its inspections is added or taken after
that. So the whole UTC hours of the open days that have closed are counted once per station, claimed
like a day (INSERT ... ON CONFLICT DO NOTHING: only the transaction that inserted an hour counts it),
and only the rest of the open days (the part of an hour before the day's first whole UTC hour, in
zones with half-hour offsets, and the last hour or two) is counted live. Hours are zone-free; those
that began two days before the hours being stored are pruned then.
"""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any, cast

from sqlalchemy import ScalarSelect, Table, delete, func, select
from sqlalchemy.orm import Session

from app.db import begin_write
from app.statistics.models import StatisticsHour, StatisticsHourStation
from app.statistics.stored import CLOSED_AFTER, claim, count_per_station

HOUR = timedelta(hours=1)
KEPT_FOR = timedelta(days=2)
_HOUR = cast(Table, StatisticsHour.__table__)
_HOUR_STATION = cast(Table, StatisticsHourStation.__table__)


def closed_hours(start: datetime, end: datetime, now: datetime) -> tuple[datetime, datetime]:
    """The whole UTC hours within [start, end) closed at `now`, as [first, until) (empty: equal)."""
    first = _hour_of(start)
    if first < start:
        first += HOUR
    until = min(_hour_of(end), _hour_of(now - CLOSED_AFTER))
    return first, max(first, until)


def _hour_of(moment: datetime) -> datetime:
    """The start of the UTC hour `moment` falls in."""
    return moment.astimezone(UTC).replace(minute=0, second=0, microsecond=0)


def hours_between(first: datetime, until: datetime) -> int:
    """How many hours there are from `first` up to `until` (whole hours apart)."""
    return int((until - first) / HOUR)


def stored_between(first: Any, until: Any) -> ScalarSelect[int]:
    """How many hours from `first` up to `until` (values or bound parameters) are stored."""
    return select(func.count()).where(_HOUR.c.starts_at >= first, _HOUR.c.starts_at < until).scalar_subquery()


def store_hours(session: Session, first: datetime, until: datetime) -> int:
    """Count and store the hours from `first` up to `until` (closed ones only) not stored yet; how
    many were counted. Commits when it stored anything."""
    wanted = hours_between(first, until)
    if not wanted:
        return 0
    stored = session.scalar(select(stored_between(first, until)))
    if stored == wanted:
        return 0  # a visit's usual case: one more hour closes once an hour
    begin_write(session)
    for table in (_HOUR_STATION, _HOUR):
        session.execute(delete(table).where(table.c.starts_at < first - KEPT_FOR))
    hours = [first + i * HOUR for i in range(wanted)]
    claimed = claim(session, _HOUR, [{"starts_at": h, "ends_at": h + HOUR} for h in hours], _HOUR.c.starts_at)
    if claimed:
        count_per_station(session, _HOUR, [_HOUR.c.starts_at], _HOUR.c.starts_at.in_(claimed), _HOUR_STATION)
    session.commit()
    return len(claimed)
