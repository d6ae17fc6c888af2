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

from sqlalchemy import Table, and_, delete, func, select
from sqlalchemy.orm import Session

from app.db import begin_write
from app.inspections.models import Inspection
from app.statistics.models import NO_STATION, StatisticsHour, StatisticsHourStation
from app.statistics.stored import CLOSED_AFTER, compliant_count, insert_for

HOUR = timedelta(hours=1)
KEPT_FOR = timedelta(days=2)
_HOUR = cast(Table, StatisticsHour.__table__)
_HOUR_STATION = cast(Table, StatisticsHourStation.__table__)
_INSPECTION = cast(Table, Inspection.__table__)


def closed_hours(start: datetime, end: datetime, now: datetime) -> tuple[datetime, datetime]:
    """The whole UTC hours within [start, end) closed at `now`, as [first, until) (empty: equal)."""
    first = _hour_of(start) if start == _hour_of(start) else _hour_of(start) + HOUR
    until = min(_hour_of(end), _hour_of(now - CLOSED_AFTER))
    return first, max(first, until)


def _hour_of(moment: datetime) -> datetime:
    """The start of the UTC hour `moment` falls in."""
    return moment.astimezone(UTC).replace(minute=0, second=0, microsecond=0)


def store_hours(session: Session, first: datetime, until: datetime) -> int:
    """Count and store the hours from `first` up to `until` (closed ones only) not stored yet; how
    many were counted. Commits when it stored anything."""
    wanted = int((until - first) / HOUR)
    if not wanted:
        return 0
    stored = session.scalar(select(func.count()).where(_HOUR.c.starts_at >= first, _HOUR.c.starts_at < until))
    if stored == wanted:
        return 0  # a visit's usual case: one more hour closes once an hour
    begin_write(session)
    for table in (_HOUR_STATION, _HOUR):
        session.execute(delete(table).where(table.c.starts_at < first - KEPT_FOR))
    hours = [first + i * HOUR for i in range(wanted)]
    claim = insert_for(session)(_HOUR).values([{"starts_at": h, "ends_at": h + HOUR} for h in hours])
    claimed = list(session.scalars(claim.on_conflict_do_nothing().returning(_HOUR.c.starts_at)))
    if claimed:
        _count_inspections(session, claimed)
    session.commit()
    return len(claimed)


def _count_inspections(session: Session, hours: list[datetime]) -> None:
    """One row per claimed hour and station with inspections, counted inside the database."""
    station = func.coalesce(_INSPECTION.c.station_id, NO_STATION)
    in_hour = and_(_INSPECTION.c.created_at >= _HOUR.c.starts_at, _INSPECTION.c.created_at < _HOUR.c.ends_at)
    counts: Any = (
        select(_HOUR.c.starts_at, station, func.count(), compliant_count(_INSPECTION.c.compliant))
        .select_from(_HOUR.join(_INSPECTION, in_hour))
        .where(_HOUR.c.starts_at.in_(hours))
        .group_by(_HOUR.c.starts_at, station)
    )
    columns = ["starts_at", "station_id", "inspections", "compliant"]
    session.execute(_HOUR_STATION.insert().from_select(columns, counts))
