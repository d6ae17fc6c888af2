"""Statistics for regulators: inspections per local day and per station, compliant or not, certificates.

Days are calendar days in the officers' zone. Closed days are read from their stored counts
(app/statistics/stored.py: taken once from the records, which never change for a day that has
ended), so a year costs the same at any size of the history. The open days (today, and yesterday
during the first hour after midnight) add up their closed UTC hours' stored counts
(app/statistics/hours.py) and count only the rest live from the records: the last one to two
hours, and in zones with a half-hour offset the day's first half hour.

Counting a whole period live (the full count), the database groups the inspections by the quarter
hour (UTC) they were made in, which needs no time-zone support from SQLite; each quarter hour then
falls on one local day in Python, so a zone's daylight-saving changes and half-hour offsets are
respected. That is at most 96 groups a day, read through the index on `created_at`. The same
functions are the full count the stored counts are tested against.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, date, datetime, time, timedelta, tzinfo
from functools import lru_cache
from typing import Any

from sqlalchemy import (
    ColumnElement,
    Select,
    bindparam,
    case,
    func,
    literal,
    select,
    union_all,
)
from sqlalchemy.orm import Session

from app.db import epoch_seconds, utcnow
from app.inspections.models import Inspection
from app.stations.models import Station
from app.statistics import hours, stored
from app.statistics.models import NO_STATION, StatisticsHourStation

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
    return epoch_seconds(session.get_bind().dialect.name, Inspection.created_at) // BUCKET_SECONDS


def daily_counts(
    session: Session, *, period: Period, zone: tzinfo, station_id: int | None = None
) -> list[DayCounts]:
    """Inspections per local day of the period, every day listed (zero when none), oldest first."""
    start, end = period.utc_bounds(zone)
    bucket = _quarter_hour(session).label("bucket")
    query = (
        select(bucket, func.count(), stored.compliant_count(Inspection.compliant))
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
        select(
            Inspection.station_id, Station.name, func.count(), stored.compliant_count(Inspection.compliant)
        )
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
    """Certificates and refusals issued, and certificates revoked, in the period (one statement)."""
    start, end = period.utc_bounds(zone)
    counts = session.execute(_certificates_query(), {"start": start, "end": end}).one()
    return int(counts[0]), int(counts[1]), int(counts[2])


@lru_cache(maxsize=1)
def _certificates_query() -> Select[int, int, int]:
    """Certificates issued, refusals issued and certificates revoked from `start` to `end` (bound)."""
    issued, refusals, revoked = stored.certificate_counts_between(bindparam("start"), bindparam("end"))
    return select(issued, refusals, revoked)


class _Tally:
    """The counts of a period being added up from its stored and its live part: plain numbers
    until the end (a year's visit adds up hundreds of them, and each Counts made costs more)."""

    def __init__(self, period: Period) -> None:
        self.days = {period.first + timedelta(days=i): [0, 0] for i in range(period.days)}
        self.stations: dict[int | None, tuple[str | None, list[int]]] = {}
        self.certificates = [0, 0, 0]  # certificates issued, refusals issued, certificates revoked

    def add_day(self, day: date, inspections: int, compliant: int) -> None:
        counts = self.days[day]
        counts[0] += inspections
        counts[1] += compliant

    def add_station(self, station_id: int | None, name: str | None, inspections: int, compliant: int) -> None:
        counts = self.stations.setdefault(station_id, (name, [0, 0]))[1]
        counts[0] += inspections
        counts[1] += compliant

    def add_certificates(self, counts: tuple[int, int, int]) -> None:
        self.certificates = [mine + theirs for mine, theirs in zip(self.certificates, counts, strict=True)]

    def day_counts(self) -> list[DayCounts]:
        """Every day of the period with its counts, oldest first."""
        return [DayCounts(day, Counts(n, ok)) for day, (n, ok) in self.days.items()]

    def total(self) -> Counts:
        """The period's counts, every day together."""
        return Counts(sum(n for n, _ in self.days.values()), sum(ok for _, ok in self.days.values()))

    def station_counts(self) -> list[StationCounts]:
        """The stations with inspections, the busiest first."""
        found = [StationCounts(sid, name, Counts(n, ok)) for sid, (name, (n, ok)) in self.stations.items()]
        return sorted(found, key=_busiest_first)


def _add_stored(
    tally: _Tally, session: Session, *, closed: Period, zone: tzinfo, station_id: int | None
) -> None:
    """The closed days' stored counts (counted from the records first where missing)."""
    first, last = closed.first, closed.last
    issued = refusals = revoked = 0
    # Unpacked, not read by name: a row's attributes cost more than the rest of a year's loop.
    for day, _, _, inspections, compliant, day_issued, day_refusals, day_revoked in stored.closed_days(
        session, zone=zone, first=first, last=last
    ):
        if station_id is None:
            tally.add_day(day, inspections, compliant)
        issued += day_issued
        refusals += day_refusals
        revoked += day_revoked
    tally.add_certificates((issued, refusals, revoked))
    if station_id is not None:
        for day, inspections, compliant in stored.stored_daily(
            session, zone=zone, first=first, last=last, station_id=station_id
        ):
            tally.add_day(day, inspections, compliant)
    for sid, name, inspections, compliant in stored.stored_stations(
        session, zone=zone, first=first, last=last, station_id=station_id
    ):
        tally.add_station(sid, name, inspections, compliant)


def _add_live(
    tally: _Tally,
    session: Session,
    *,
    live: Period,
    zone: tzinfo,
    station_id: int | None,
    now: datetime,
) -> None:
    """The open days counted from the records (and their closed hours' stored counts)."""
    counted = open_days(session, period=live, zone=zone, station_id=station_id, now=now)
    for day, sid, name, counts in counted.per_station:
        tally.add_day(day, counts.inspections, counts.compliant)
        tally.add_station(sid, name, counts.inspections, counts.compliant)
    tally.add_certificates(counted.certificates)


@dataclass(frozen=True)
class OpenDays:
    """The open days' counts: (day, station id, station name, counts) for each day and station with
    inspections, and the certificates and refusals issued and certificates revoked in them."""

    per_station: list[tuple[date, int | None, str | None, Counts]]
    certificates: tuple[int, int, int]


def open_days(
    session: Session,
    *,
    period: Period,
    zone: tzinfo,
    station_id: int | None = None,
    now: datetime | None = None,
) -> OpenDays:
    """The counts of a short period (the open days: one or two), in one statement: the whole UTC
    hours closed at `now` (default: the current time) from their stored counts (stored here first
    where missing), the rest live.

    Each inspection's (and hour's) day is told by comparing its time with the UTC starts of the
    period's days, worked out in Python, so the database needs no time-zone support.
    """
    days = [period.first + timedelta(days=i) for i in range(period.days)]
    start, end = period.utc_bounds(zone)
    hours_from, hours_until = hours.closed_hours(start, end, now or utcnow())
    span: dict[str, Any] = {f"starts_{i}": stored.day_bounds(day, zone)[0] for i, day in enumerate(days)}
    span |= {"start": start, "hours_from": hours_from, "hours_until": hours_until, "end": end}
    span["station_id"] = station_id
    query = _open_days_query(days=len(days), one_station=station_id is not None)
    rows = session.execute(query, span).all()
    if rows[0].hours_stored < hours.hours_between(hours_from, hours_until):  # the counts read lack some
        hours.store_hours(session, hours_from, hours_until)
        rows = session.execute(query, span).all()
    per_station = [
        (days[int(number)], None if sid == NO_STATION else sid, name, Counts(int(n), int(ok)))
        for *_, number, sid, name, n, ok in rows
        if sid is not None  # None: the facts' row of a period without inspections
    ]
    return OpenDays(per_station, (int(rows[0].issued), int(rows[0].refusals), int(rows[0].revoked)))


# Built once per shape, with bound parameters: building the statement cost as much as running it.
@lru_cache(maxsize=16)
def _open_days_query(*, days: int, one_station: bool) -> Select[Any]:
    """Inspections from `start` to `end` per day number (day i starts at `starts_i`) and station:
    the stored hours from `hours_from` up to `hours_until`, the rest from the records; with
    `one_station`, at station `station_id` only. Each row starts with `hours_stored` (how many of
    those hours are stored) and the certificates and refusals `issued`, `refusals`, and the
    certificates `revoked` from `start` to `end`."""

    def day_number(moment: Any) -> Any:
        later_days = [(moment >= bindparam(f"starts_{i}"), i) for i in range(days - 1, 0, -1)]
        return case(*later_days, else_=0) if later_days else literal(0)

    def live(since: str, until: str) -> Select[Any]:
        at = Inspection.created_at
        return select(
            day_number(at).label("day_number"),
            func.coalesce(Inspection.station_id, NO_STATION).label("station_id"),
            literal(1).label("n"),
            case((Inspection.compliant, 1), else_=0).label("ok"),
        ).where(at >= bindparam(since), at < bindparam(until))

    hour = StatisticsHourStation
    closed_hours = select(
        day_number(hour.starts_at), hour.station_id, hour.inspections, hour.compliant
    ).where(hour.starts_at >= bindparam("hours_from"), hour.starts_at < bindparam("hours_until"))
    # Three ranges apart: one OR would scan the stored hours' inspections too.
    parts = [live("start", "hours_from"), closed_hours, live("hours_until", "end")]
    if one_station:
        parts = [part.where(part.selected_columns.station_id == bindparam("station_id")) for part in parts]
    rows = union_all(*parts).subquery()
    issued, refusals, revoked = stored.certificate_counts_between(bindparam("start"), bindparam("end"))
    return stored.with_facts(
        stored.summed_by_station(rows, rows.c.day_number),
        hours_stored=hours.stored_between(bindparam("hours_from"), bindparam("hours_until")),
        issued=issued,
        refusals=refusals,
        revoked=revoked,
    )


def statistics(
    session: Session,
    *,
    period: Period,
    zone: tzinfo,
    station_id: int | None = None,
    now: datetime | None = None,
) -> Statistics:
    """The counts of a period: per day, per station, in total, and the certificates issued and revoked.

    The closed days come from their stored counts, the open ones are counted live (but for their
    closed hours' stored counts); `now` (default: the current time) decides which days and hours
    are closed.
    """
    now = now or utcnow()
    last_closed = min(period.last, stored.last_closed_day(zone, now))
    first_open = max(period.first, last_closed + timedelta(days=1))
    tally = _Tally(period)
    if period.first <= last_closed:
        closed = Period(period.first, last_closed)
        _add_stored(tally, session, closed=closed, zone=zone, station_id=station_id)
    if first_open <= period.last:
        live = Period(first_open, period.last)
        _add_live(tally, session, live=live, zone=zone, station_id=station_id, now=now)
    issued, refusals, revoked = tally.certificates
    days, stations = tally.day_counts(), tally.station_counts()
    return Statistics(period, tally.total(), days, stations, issued, refusals, revoked)


def _busiest_first(station: StationCounts) -> tuple[int, bool, str]:
    """Most inspections first; among equals by name, the officers' pages (no station) last."""
    return -station.counts.inspections, station.station is None, station.station or ""


def busiest(days: Sequence[DayCounts]) -> int:
    """The largest number of inspections on one day of the period (0 when there were none)."""
    return max((d.counts.inspections for d in days), default=0)
