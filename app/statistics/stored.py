"""The counts of closed local days, taken once from the records and stored (derived data, not records).

A local day is closed an hour after it ends in its zone: an inspection or certificate takes its time
stamp moments before its commit, so by then every row of the day is committed, and, the records
being append-only, none is ever added to it or taken from it. Its counts are taken on the first
request that needs them (or by `trikecert count-statistics`), set-based: the day's row is claimed by
an INSERT ... ON CONFLICT DO NOTHING, and only the transaction that inserted it counts the day, so
concurrent requests and worker processes never count a day twice (SQLite: one writer at a time).
The day keeps the UTC bounds it was counted over: after a change of the display zone the new zone's
days are counted afresh under its own name, and a day whose bounds the zone's rules no longer give
(a tzdata update) is counted again.
"""

from __future__ import annotations

from collections.abc import Iterable
from datetime import UTC, date, datetime, time, timedelta, tzinfo
from typing import Any, cast

from sqlalchemy import Table, and_, case, delete, func, select, update
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import Session

from app.certificates.models import Certificate, CertificateRevocation
from app.db import begin_write
from app.inspections.models import Inspection
from app.stations.models import Station
from app.statistics.models import NO_STATION, StatisticsDay, StatisticsDayStation

CLOSED_AFTER = timedelta(hours=1)
_DAY = cast(Table, StatisticsDay.__table__)
_DAY_STATION = cast(Table, StatisticsDayStation.__table__)
_INSPECTION = cast(Table, Inspection.__table__)


def zone_name(zone: tzinfo) -> str:
    """The name the zone's days are stored under: its IANA key (Africa/Lagos), else its own name (UTC)."""
    return str(getattr(zone, "key", None) or datetime.now(zone).tzname() or "UTC")


def day_bounds(day: date, zone: tzinfo) -> tuple[datetime, datetime]:
    """The UTC start of the local day and the UTC start of the next one."""
    start = datetime.combine(day, time.min, tzinfo=zone).astimezone(UTC)
    end = datetime.combine(day + timedelta(days=1), time.min, tzinfo=zone).astimezone(UTC)
    return start, end


def last_closed_day(zone: tzinfo, now: datetime) -> date:
    """The latest local day that ended at least CLOSED_AFTER before `now`."""
    return (now - CLOSED_AFTER).astimezone(zone).date() - timedelta(days=1)


def _days(first: date, last: date) -> list[date]:
    return [first + timedelta(days=i) for i in range((last - first).days + 1)]


def _insert(session: Session) -> Any:
    return postgresql.insert if session.get_bind().dialect.name == "postgresql" else sqlite.insert


def count_closed_days(session: Session, *, zone: tzinfo, first: date, last: date) -> int:
    """Store the counts of the closed days `first` to `last` not stored yet; how many were counted.

    The caller passes closed days only (see last_closed_day). Commits when it stored anything.
    """
    name = zone_name(zone)
    wanted = {day: day_bounds(day, zone) for day in _days(first, last)}
    stored = {
        day: (starts_at, ends_at)
        for day, starts_at, ends_at in session.execute(
            select(_DAY.c.day, _DAY.c.starts_at, _DAY.c.ends_at).where(
                _DAY.c.zone == name, _DAY.c.day >= first, _DAY.c.day <= last
            )
        )
    }
    stale = [day for day, bounds in stored.items() if wanted[day] != bounds]
    missing = [day for day in wanted if day not in stored or day in stale]
    if not missing:
        return 0
    begin_write(session)
    if stale:
        for table in (_DAY_STATION, _DAY):
            session.execute(delete(table).where(table.c.zone == name, table.c.day.in_(stale)))
    zero = {"certificates_issued": 0, "refusals_issued": 0, "certificates_revoked": 0}
    rows = [
        {"zone": name, "day": day, "starts_at": wanted[day][0], "ends_at": wanted[day][1], **zero}
        for day in missing
    ]
    claim = _insert(session)(_DAY).values(rows)
    claimed = list(session.scalars(claim.on_conflict_do_nothing().returning(_DAY.c.day)))
    if claimed:
        _count_inspections(session, name, claimed)
        _count_certificates(session, name, claimed)
    session.commit()
    return len(claimed)


def _count_inspections(session: Session, name: str, days: list[date]) -> None:
    """One row per claimed day and station with inspections, counted inside the database."""
    station = func.coalesce(_INSPECTION.c.station_id, NO_STATION)
    compliant = func.coalesce(func.sum(case((_INSPECTION.c.compliant, 1), else_=0)), 0)
    in_day = and_(_INSPECTION.c.created_at >= _DAY.c.starts_at, _INSPECTION.c.created_at < _DAY.c.ends_at)
    counts = (
        select(_DAY.c.zone, _DAY.c.day, station, func.count(), compliant)
        .select_from(_DAY.join(_INSPECTION, in_day))
        .where(_DAY.c.zone == name, _DAY.c.day.in_(days))
        .group_by(_DAY.c.zone, _DAY.c.day, station)
    )
    columns = ["zone", "day", "station_id", "inspections", "compliant"]
    session.execute(_DAY_STATION.insert().from_select(columns, counts))


def _count_certificates(session: Session, name: str, days: list[date]) -> None:
    """The claimed days' certificates and refusals issued and certificates revoked."""

    def issued(compliant: bool) -> Any:
        return (
            select(func.count())
            .where(
                Certificate.compliant == compliant,
                Certificate.issued_at >= _DAY.c.starts_at,
                Certificate.issued_at < _DAY.c.ends_at,
            )
            .scalar_subquery()
        )

    revoked = (
        select(func.count())
        .where(
            CertificateRevocation.revoked_at >= _DAY.c.starts_at,
            CertificateRevocation.revoked_at < _DAY.c.ends_at,
        )
        .scalar_subquery()
    )
    session.execute(
        update(_DAY)
        .where(_DAY.c.zone == name, _DAY.c.day.in_(days))
        .values(certificates_issued=issued(True), refusals_issued=issued(False), certificates_revoked=revoked)
    )


def stored_daily(
    session: Session, *, zone: tzinfo, first: date, last: date, station_id: int | None = None
) -> Iterable[tuple[date, int, int]]:
    """(day, inspections, compliant) of the stored days `first` to `last` that had inspections."""
    query = (
        select(_DAY_STATION.c.day, func.sum(_DAY_STATION.c.inspections), func.sum(_DAY_STATION.c.compliant))
        .where(_in_period(zone, first, last))
        .group_by(_DAY_STATION.c.day)
    )
    if station_id is not None:
        query = query.where(_DAY_STATION.c.station_id == station_id)
    return [(day, int(n), int(ok)) for day, n, ok in session.execute(query)]


def stored_stations(
    session: Session, *, zone: tzinfo, first: date, last: date, station_id: int | None = None
) -> Iterable[tuple[int | None, str | None, int, int]]:
    """(station id, name, inspections, compliant) over the stored days; the officers' pages as None."""
    sid = _DAY_STATION.c.station_id
    query = (
        select(sid, Station.name, func.sum(_DAY_STATION.c.inspections), func.sum(_DAY_STATION.c.compliant))
        .outerjoin(Station, Station.id == sid)
        .where(_in_period(zone, first, last))
        .group_by(sid, Station.name)
    )
    if station_id is not None:
        query = query.where(sid == station_id)
    return [
        (None if station == NO_STATION else station, name, int(n), int(ok))
        for station, name, n, ok in session.execute(query)
    ]


def stored_certificates(session: Session, *, zone: tzinfo, first: date, last: date) -> tuple[int, int, int]:
    """Certificates and refusals issued, and certificates revoked, over the stored days."""
    sums = session.execute(
        select(
            func.coalesce(func.sum(_DAY.c.certificates_issued), 0),
            func.coalesce(func.sum(_DAY.c.refusals_issued), 0),
            func.coalesce(func.sum(_DAY.c.certificates_revoked), 0),
        ).where(_DAY.c.zone == zone_name(zone), _DAY.c.day >= first, _DAY.c.day <= last)
    ).one()
    return int(sums[0]), int(sums[1]), int(sums[2])


def _in_period(zone: tzinfo, first: date, last: date) -> Any:
    table = _DAY_STATION
    return and_(table.c.zone == zone_name(zone), table.c.day >= first, table.c.day <= last)
