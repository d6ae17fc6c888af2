"""How many inspections a list's filter matches, at a cost that does not grow with the history.

The closed local days that a period covers whole are read from their stored counts (per day and
station, app/statistics/stored.py: counted once from the records, then kept, the records being
append-only); only the two ends of the period that are not whole closed days (at most a day and
the open day at each end) are counted from the records. The sum is exactly a full count: the days
partition the time line, each day's stored bounds are the zone's own, and the ends are counted
over the rest of the period.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import date, datetime, timedelta, tzinfo
from typing import Any

from sqlalchemy import ColumnElement, func, select
from sqlalchemy.orm import Session

from app.inspections.models import Inspection
from app.statistics import stored
from app.statistics.models import StatisticsDayStation

# Below this many whole closed days the period is counted from the records alone.
FEWEST_STORED_DAYS = 2


def count_matching(
    session: Session,
    *,
    conditions: Sequence[ColumnElement[bool]],
    values: Mapping[str, Any],
    since: datetime | None,
    until: datetime | None,
    compliant: bool | None,
    station_id: int | None,
    zone: tzinfo,
    now: datetime,
) -> int:
    """How many inspections match `conditions` (the filter's, its period included, on bound
    parameters given by `values`).

    `since`, `until`, `compliant` and `station_id` are the filter's own, for the stored days;
    `zone` is the one whose days are stored (the display zone), `now` decides which are closed.
    """
    first_inspection = _first_time(session)
    if first_inspection is None:
        return 0  # no inspection at all
    # No day before the first inspection is stored (or counted): a period from the year 1472 costs
    # what one from the first inspection costs.
    start = first_inspection if since is None else max(since, first_inspection)
    days = _whole_closed_days(start, until, zone, now)
    if days is None:
        return _count_live(session, conditions, values)
    first, last = days
    covered_from, _ = stored.day_bounds(first, zone)
    _, covered_until = stored.day_bounds(last, zone)
    stored.count_closed_days(session, zone=zone, first=first, last=last)
    # The two ends apart: each is a short range of the created_at index (one OR would scan between).
    before = _count_live(session, [*conditions, Inspection.created_at < covered_from], values)
    after = _count_live(session, [*conditions, Inspection.created_at >= covered_until], values)
    return before + _stored_sum(session, zone, first, last, compliant, station_id) + after


def count_matching_inspections(
    session: Session,
    *,
    conditions: Sequence[ColumnElement[bool]],
    values: Mapping[str, Any],
    since: datetime | None,
    until: datetime | None,
    compliant: bool | None,
    station_id: int | None,
    now: datetime,
) -> int:
    """count_matching in the zone whose days are stored (the display zone): the counter a list of
    inspections uses (app/inspections/service.py, count_matches_with)."""
    return count_matching(
        session,
        conditions=conditions,
        values=values,
        since=since,
        until=until,
        compliant=compliant,
        station_id=station_id,
        zone=stored.stored_zone(),
        now=now,
    )


def _first_time(session: Session) -> datetime | None:
    return session.scalar(select(func.min(Inspection.created_at)))


def _whole_closed_days(
    start: datetime, until: datetime | None, zone: tzinfo, now: datetime
) -> tuple[date, date] | None:
    """The first and last closed local days inside [start, until), or None when too few."""
    first = start.astimezone(zone).date()
    if stored.day_bounds(first, zone)[0] < start:
        first += timedelta(days=1)
    last = stored.last_closed_day(zone, now)
    # An `until` after the last closed day leaves it last; only an earlier one is worked out in the
    # zone (one near the year 9999 would not even fit a date there).
    if until is not None and until < stored.day_bounds(last, zone)[1]:
        last = until.astimezone(zone).date()
        if stored.day_bounds(last, zone)[1] > until:
            last -= timedelta(days=1)
    if (last - first).days + 1 < FEWEST_STORED_DAYS:
        return None
    return first, last


def _stored_sum(
    session: Session, zone: tzinfo, first: date, last: date, compliant: bool | None, station_id: int | None
) -> int:
    """The matching inspections of the stored days `first` to `last`, from their counts."""
    row = StatisticsDayStation
    inspections, complying = session.execute(
        select(func.coalesce(func.sum(row.inspections), 0), func.coalesce(func.sum(row.compliant), 0)).where(
            row.zone == stored.zone_name(zone),
            row.day >= first,
            row.day <= last,
            *([] if station_id is None else [row.station_id == station_id]),
        )
    ).one()
    if compliant is None:
        return int(inspections)
    return int(complying) if compliant else int(inspections) - int(complying)


def _count_live(
    session: Session, conditions: Sequence[ColumnElement[bool]], values: Mapping[str, Any]
) -> int:
    query = select(func.count()).select_from(Inspection).where(*conditions)
    return int(session.scalar(query, dict(values)) or 0)
