"""Statistics for regulators: inspections per local day and per station, compliant or not, certificates.

Days are calendar days in the officers' zone. The database groups the inspections of the period by
the quarter hour (UTC) they were made in, which needs no time-zone support from SQLite; each quarter
hour then falls on one local day in Python, so a zone's daylight-saving changes and half-hour
offsets are respected. That is at most 96 groups a day, read through the index on `created_at`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, date, datetime, time, timedelta, tzinfo

from sqlalchemy import BigInteger, ColumnElement, Integer, case, cast, func, select
from sqlalchemy.orm import Session

from app.certificates.models import Certificate, CertificateRevocation
from app.inspections.models import Inspection
from app.stations.models import Station

BUCKET_SECONDS = 900  # a quarter hour: every time zone's offset is a whole number of them
MAX_DAYS = 366


@dataclass(frozen=True)
class Counts:
    """Inspections and how many of them complied."""

    inspections: int = 0
    compliant: int = 0

    @property
    def not_compliant(self) -> int:
        """Inspections that did not comply."""
        return self.inspections - self.compliant

    @property
    def compliant_percent(self) -> float | None:
        """The share that complied, in per cent (None without inspections)."""
        return 100 * self.compliant / self.inspections if self.inspections else None

    def __add__(self, other: Counts) -> Counts:
        return Counts(self.inspections + other.inspections, self.compliant + other.compliant)


@dataclass(frozen=True)
class DayCounts:
    """One local calendar day's counts."""

    day: date
    counts: Counts


@dataclass(frozen=True)
class StationCounts:
    """One station's counts; `station` None for inspections entered by officers in the pages."""

    station_id: int | None
    station: str | None
    counts: Counts


@dataclass(frozen=True)
class Period:
    """Local calendar days `first` to `last`, both included."""

    first: date
    last: date

    @property
    def days(self) -> int:
        """How many days the period has."""
        return (self.last - self.first).days + 1

    def utc_bounds(self, zone: tzinfo) -> tuple[datetime, datetime]:
        """The UTC start of the first day and the UTC start of the day after the last."""
        start = datetime.combine(self.first, time.min, tzinfo=zone).astimezone(UTC)
        end = datetime.combine(self.last + timedelta(days=1), time.min, tzinfo=zone).astimezone(UTC)
        return start, end


@dataclass(frozen=True)
class Statistics:
    """Everything the statistics page shows for one period (and optionally one station)."""

    period: Period
    total: Counts
    days: list[DayCounts]
    stations: list[StationCounts]
    certificates_issued: int
    refusals_issued: int
    certificates_revoked: int


def _quarter_hour(session: Session) -> ColumnElement[int]:
    """The number of the quarter hour since 1970 (UTC) an inspection was made in."""
    if session.get_bind().dialect.name == "postgresql":
        epoch = func.extract("epoch", Inspection.created_at)
        return cast(func.floor(epoch / BUCKET_SECONDS), BigInteger)
    # SQLite keeps UTC as text; strftime('%s') reads it as seconds since 1970.
    return cast(func.strftime("%s", Inspection.created_at), Integer) // BUCKET_SECONDS


def _compliant_count() -> ColumnElement[int]:
    return func.coalesce(func.sum(case((Inspection.compliant, 1), else_=0)), 0)


def daily_counts(
    session: Session, *, period: Period, zone: tzinfo, station_id: int | None = None
) -> list[DayCounts]:
    """Inspections per local day of the period, every day listed (zero when none), oldest first."""
    start, end = period.utc_bounds(zone)
    bucket = _quarter_hour(session).label("bucket")
    query = (
        select(bucket, func.count(), _compliant_count())
        .where(Inspection.created_at >= start, Inspection.created_at < end)
        .group_by(bucket)
    )
    if station_id is not None:
        query = query.where(Inspection.station_id == station_id)
    per_day = {period.first + timedelta(days=i): Counts() for i in range(period.days)}
    for quarter, inspections, compliant in session.execute(query):
        moment = datetime.fromtimestamp(int(quarter) * BUCKET_SECONDS, UTC)
        day = moment.astimezone(zone).date()
        if day in per_day:
            per_day[day] += Counts(int(inspections), int(compliant))
    return [DayCounts(day, counts) for day, counts in per_day.items()]


def station_counts(
    session: Session, *, period: Period, zone: tzinfo, station_id: int | None = None
) -> list[StationCounts]:
    """Inspections per station over the period, the busiest first; officers' entries as station None."""
    start, end = period.utc_bounds(zone)
    query = (
        select(Inspection.station_id, Station.name, func.count(), _compliant_count())
        .outerjoin(Station, Station.id == Inspection.station_id)
        .where(Inspection.created_at >= start, Inspection.created_at < end)
        .group_by(Inspection.station_id, Station.name)
        .order_by(func.count().desc(), Station.name)
    )
    if station_id is not None:
        query = query.where(Inspection.station_id == station_id)
    return [
        StationCounts(sid, name, Counts(int(inspections), int(compliant)))
        for sid, name, inspections, compliant in session.execute(query)
    ]


def certificate_counts(session: Session, *, period: Period, zone: tzinfo) -> tuple[int, int, int]:
    """Certificates and refusals issued, and certificates revoked, in the period."""
    start, end = period.utc_bounds(zone)
    issued = session.execute(
        select(Certificate.compliant, func.count())
        .where(Certificate.issued_at >= start, Certificate.issued_at < end)
        .group_by(Certificate.compliant)
    ).all()
    by_kind = {bool(compliant): int(n) for compliant, n in issued}
    revoked = session.scalar(
        select(func.count()).where(
            CertificateRevocation.revoked_at >= start, CertificateRevocation.revoked_at < end
        )
    )
    return by_kind.get(True, 0), by_kind.get(False, 0), int(revoked or 0)


def statistics(
    session: Session, *, period: Period, zone: tzinfo, station_id: int | None = None
) -> Statistics:
    """The counts of a period: per day, per station, in total, and the certificates issued and revoked."""
    days = daily_counts(session, period=period, zone=zone, station_id=station_id)
    total = sum((d.counts for d in days), Counts())
    stations = station_counts(session, period=period, zone=zone, station_id=station_id)
    issued, refusals, revoked = certificate_counts(session, period=period, zone=zone)
    return Statistics(period, total, days, stations, issued, refusals, revoked)


def busiest(days: Sequence[DayCounts]) -> int:
    """The largest number of inspections on one day of the period (0 when there were none)."""
    return max((d.counts.inspections for d in days), default=0)
