"""The counts of closed local days, taken once from the records and stored (derived data, not records).

A local day is closed an hour after it ends in its zone: an inspection or certificate takes its time
stamp moments before its commit, so by then every row of the day is committed, and, the records
being append-only, none is ever added to it or taken from it. Its counts are taken on the first
request that needs them (or by `trikecert count-statistics`), set-based: the day's row is claimed by
an INSERT ... ON CONFLICT DO NOTHING, and only the transaction that inserted it counts the day, so
concurrent requests and worker processes never count a day twice (SQLite: one writer at a time).
The day keeps the UTC bounds it was counted over: after a change of the display zone the new zone's
days are counted afresh under its own name, and a day whose bounds the zone's rules no longer give
(a tzdata update) is counted again. A calendar month whose days are all stored gets its per-station
sums stored too (once, claimed the same way), so a year's per-station sums add up eleven or twelve
months and the days at the period's ends; a day counted again drops its month's sums.
"""

from __future__ import annotations

from collections.abc import Iterable
from datetime import UTC, date, datetime, time, timedelta, tzinfo
from functools import lru_cache
from typing import Any, cast
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

from sqlalchemy import (
    BindParameter,
    Column,
    ColumnElement,
    Date,
    Row,
    ScalarSelect,
    Select,
    String,
    Subquery,
    Table,
    and_,
    bindparam,
    case,
    delete,
    func,
    literal,
    select,
    true,
    union_all,
    update,
)
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import InstrumentedAttribute, Session

from app.certificates.models import Certificate, CertificateRevocation
from app.config import get_settings
from app.db import begin_write, epoch_seconds
from app.inspections.models import Inspection
from app.stations.models import Station
from app.statistics.models import (
    NO_STATION,
    StatisticsDay,
    StatisticsDayStation,
    StatisticsMonth,
    StatisticsMonthStation,
)

CLOSED_AFTER = timedelta(hours=1)
DAYS_PER_BATCH = 366
_DAY = cast(Table, StatisticsDay.__table__)
_DAY_STATION = cast(Table, StatisticsDayStation.__table__)
_MONTH = cast(Table, StatisticsMonth.__table__)
_MONTH_STATION = cast(Table, StatisticsMonthStation.__table__)
_INSPECTION = cast(Table, Inspection.__table__)
# A stored day as read: the day, its UTC bounds as seconds since 1970, and its _COUNTS.
StoredDay = Row[date, int, int, int, int, int, int, int]


def stored_zone() -> tzinfo:
    """The zone whose local days are stored for the lists' counts: the display zone (UTC if unknown)."""
    try:
        return ZoneInfo(get_settings().display_timezone)
    except (ZoneInfoNotFoundError, ValueError):
        return UTC


def compliant_count(compliant: ColumnElement[bool] | InstrumentedAttribute[bool]) -> ColumnElement[int]:
    """How many of the grouped rows have `compliant` true (0 for none)."""
    return func.coalesce(func.sum(case((compliant, 1), else_=0)), 0)


def zone_name(zone: tzinfo) -> str:
    """The name the zone's days are stored under: its IANA key (Africa/Lagos), else its own name (UTC)."""
    return str(getattr(zone, "key", None) or datetime.now(zone).tzname() or "UTC")


@lru_cache(maxsize=8192)
def day_bounds(day: date, zone: tzinfo) -> tuple[datetime, datetime]:
    """The UTC start of the local day and the UTC start of the next one (worked out once per day and
    zone: a year's statistics ask for 366 of them on every visit)."""
    start = datetime.combine(day, time.min, tzinfo=zone).astimezone(UTC)
    end = datetime.combine(day + timedelta(days=1), time.min, tzinfo=zone).astimezone(UTC)
    return start, end


@lru_cache(maxsize=64)
def _bounds_in_seconds(first: date, last: date, zone: tzinfo) -> dict[date, tuple[int, int]]:
    """Each day's day_bounds from `first` to `last` as whole seconds since 1970, as a stored day's
    bounds are read back (worked out once per span: a year's statistics ask for it on every visit).
    Shared between callers: not to be changed."""
    bounds = {}
    for day in _days(first, last):
        start, end = day_bounds(day, zone)
        bounds[day] = int(start.timestamp()), int(end.timestamp())
    return bounds


def last_closed_day(zone: tzinfo, now: datetime) -> date:
    """The latest local day that ended at least CLOSED_AFTER before `now`."""
    return (now - CLOSED_AFTER).astimezone(zone).date() - timedelta(days=1)


def _days(first: date, last: date) -> list[date]:
    return [first + timedelta(days=i) for i in range((last - first).days + 1)]


def _insert(session: Session) -> Any:
    """The dialect's INSERT, which has ON CONFLICT DO NOTHING, for the session's database."""
    return postgresql.insert if session.get_bind().dialect.name == "postgresql" else sqlite.insert


def _read_days(session: Session, name: str, first: date, last: date) -> list[StoredDay]:
    # Fetched whole (.all()): row by row, the driver's per-row calls cost ten times the query.
    query = _days_query(session.get_bind().dialect.name)
    return list(session.execute(query, {"zone": name, "first": first, "last": last}).all())


@lru_cache(maxsize=2)
def _days_query(dialect: str) -> Select[Any]:
    """Zone `zone`'s stored days from `first` to `last` (bound parameters), oldest first: each day, its
    bounds as seconds since 1970 (turning a year's 732 time stamps into datetimes cost ten times the
    query), its counts."""
    days = _DAY
    starts = epoch_seconds(dialect, days.c.starts_at).label("starts")
    ends = epoch_seconds(dialect, days.c.ends_at).label("ends")
    return (
        select(days.c.day, starts, ends, *(days.c[count] for count in _COUNTS))
        .where(
            days.c.zone == bindparam("zone"),
            days.c.day >= bindparam("first"),
            days.c.day <= bindparam("last"),
        )
        .order_by(days.c.day)
    )


def count_closed_days(session: Session, *, zone: tzinfo, first: date, last: date) -> int:
    """Store the counts of the closed days `first` to `last` not stored yet; how many were counted.

    The caller passes closed days only (see last_closed_day). Commits when it stored anything.
    """
    return _count_missing(session, zone, first, last, _read_days(session, zone_name(zone), first, last))


def closed_days(session: Session, *, zone: tzinfo, first: date, last: date) -> list[StoredDay]:
    """The stored rows of the closed days `first` to `last` (day, its bounds as seconds since 1970
    `starts` and `ends`, and its counts), oldest first; those not stored yet are counted first."""
    name = zone_name(zone)
    rows = _read_days(session, name, first, last)
    if _count_missing(session, zone, first, last, rows):
        rows = _read_days(session, name, first, last)
    return rows


def _count_missing(session: Session, zone: tzinfo, first: date, last: date, rows: list[StoredDay]) -> int:
    """Count the days of the span missing from `rows`, or stored over other bounds; how many."""
    name = zone_name(zone)
    wanted = _bounds_in_seconds(first, last, zone)
    stale = [day for day, starts, ends, *_ in rows if wanted[day] != (starts, ends)]
    if len(rows) == len(wanted) and not stale:
        return 0  # every day stored (one row a day), over the zone's bounds: a visit's usual case
    stored = {day for day, *_ in rows}
    missing = [day for day in wanted if day not in stored or day in stale]
    counted = 0
    # A batch at a time: years of days in one statement would pass the drivers' limit on parameters.
    for start in range(0, len(missing), DAYS_PER_BATCH):
        batch = missing[start : start + DAYS_PER_BATCH]
        counted += _count_batch(
            session, name, {day: day_bounds(day, zone) for day in batch}, [d for d in batch if d in stale]
        )
    return counted


def _count_batch(
    session: Session, name: str, bounds: dict[date, tuple[datetime, datetime]], stale: list[date]
) -> int:
    """Claim and count the days of `bounds` (after dropping their `stale` rows), in one transaction."""
    begin_write(session)
    if stale:
        for table in (_DAY_STATION, _DAY):
            session.execute(delete(table).where(table.c.zone == name, table.c.day.in_(stale)))
        months = {day.replace(day=1) for day in stale}  # their sums include the stale days
        for table in (_MONTH_STATION, _MONTH):
            session.execute(delete(table).where(table.c.zone == name, table.c.month.in_(months)))
    zero = dict.fromkeys(_COUNTS, 0)
    rows = [
        {"zone": name, "day": day, "starts_at": start, "ends_at": end, **zero}
        for day, (start, end) in bounds.items()
    ]
    claimed = claim(session, _DAY, rows, _DAY.c.day)
    if claimed:
        these_days = and_(_DAY.c.zone == name, _DAY.c.day.in_(claimed))
        count_per_station(session, _DAY, [_DAY.c.zone, _DAY.c.day], these_days, _DAY_STATION)
        _count_days(session, name, claimed)
    session.commit()
    return len(claimed)


_COUNTS = ("inspections", "compliant", "certificates_issued", "refusals_issued", "certificates_revoked")


def claim(session: Session, table: Table, rows: list[dict[str, Any]], key: Column[Any]) -> list[Any]:
    """Insert the rows not in `table` yet (INSERT ... ON CONFLICT DO NOTHING); the `key` of those this
    transaction inserted, and so is the one to count: concurrent claims of a row never both win."""
    inserted = _insert(session)(table).values(rows).on_conflict_do_nothing().returning(key)
    return list(session.scalars(inserted))


def count_per_station(
    session: Session, spans: Table, keys: list[Column[Any]], claimed: ColumnElement[bool], into: Table
) -> None:
    """Count the inspections of each `claimed` row of `spans` (a span of time with its UTC bounds
    `starts_at` and `ends_at`, named by `keys`) per station, inside the database, into `into`: one
    row per span and station with inspections (its keys, station_id, inspections, compliant)."""
    station = func.coalesce(_INSPECTION.c.station_id, NO_STATION)
    at = _INSPECTION.c.created_at
    counts = (
        select(*keys, station, func.count(), compliant_count(_INSPECTION.c.compliant))
        .select_from(spans.join(_INSPECTION, and_(at >= spans.c.starts_at, at < spans.c.ends_at)))
        .where(claimed)
        .group_by(*keys, station)
    )
    columns = [*(key.name for key in keys), "station_id", "inspections", "compliant"]
    session.execute(into.insert().from_select(columns, counts))


def _count_days(session: Session, name: str, days: list[date]) -> None:
    """The claimed days' totals: inspections at every station, certificates and refusals issued,
    certificates revoked."""

    def at_stations(column: Any) -> Any:
        return (
            select(func.coalesce(func.sum(column), 0))
            .where(_DAY_STATION.c.zone == _DAY.c.zone, _DAY_STATION.c.day == _DAY.c.day)
            .scalar_subquery()
        )

    issued, refusals, revoked = certificate_counts_between(_DAY.c.starts_at, _DAY.c.ends_at)
    session.execute(
        update(_DAY)
        .where(_DAY.c.zone == name, _DAY.c.day.in_(days))
        .values(
            inspections=at_stations(_DAY_STATION.c.inspections),
            compliant=at_stations(_DAY_STATION.c.compliant),
            certificates_issued=issued,
            refusals_issued=refusals,
            certificates_revoked=revoked,
        )
    )


def certificate_counts_between(
    start: Any, end: Any
) -> tuple[ScalarSelect[int], ScalarSelect[int], ScalarSelect[int]]:
    """Certificates issued, refusals issued and certificates revoked from `start` to `end` (columns
    or bound parameters), as three scalar subqueries."""

    def issued(compliant: bool) -> ScalarSelect[int]:
        in_period = (Certificate.issued_at >= start, Certificate.issued_at < end)
        return select(func.count()).where(Certificate.compliant.is_(compliant), *in_period).scalar_subquery()

    revoked = select(func.count()).where(
        CertificateRevocation.revoked_at >= start, CertificateRevocation.revoked_at < end
    )
    return issued(True), issued(False), revoked.scalar_subquery()


def stored_daily(
    session: Session, *, zone: tzinfo, first: date, last: date, station_id: int
) -> Iterable[tuple[date, int, int]]:
    """(day, inspections, compliant) at one station on the stored days `first` to `last` it had any."""
    query = (
        select(_DAY_STATION.c.day, func.sum(_DAY_STATION.c.inspections), func.sum(_DAY_STATION.c.compliant))
        .where(_in_period(zone_name(zone), first, last))
        .where(_DAY_STATION.c.station_id == station_id)
        .group_by(_DAY_STATION.c.day)
    )
    return [(day, int(n), int(ok)) for day, n, ok in session.execute(query).all()]


def stored_stations(
    session: Session, *, zone: tzinfo, first: date, last: date, station_id: int | None = None
) -> Iterable[tuple[int | None, str | None, int, int]]:
    """(station id, name, inspections, compliant) over the stored days `first` to `last` (every one
    stored: see closed_days); the officers' pages as None.

    The calendar months lying whole in the period are added up from their stored per-station sums
    (stored here first where missing), and only the days before and after them from the days'.
    """
    name = zone_name(zone)
    months = _whole_months(first, last)
    span = {"zone": name, "first": first, "last": last, "station_id": station_id}
    if months:
        span["months_from"], span["months_until"] = months[0], _month_after(months[-1])
        span["before_months"] = months[0] - timedelta(days=1)
    query = _stations_query(whole_months=bool(months), one_station=station_id is not None)
    rows = session.execute(query, span).all()
    if months and rows[0].months_stored < len(months):  # the sums read are short of some months
        _store_months(session, name, months)
        rows = session.execute(query, span).all()
    return [
        (None if station == NO_STATION else station, station_name, int(n), int(ok))
        for _, station, station_name, n, ok in rows
        if station is not None  # None: the facts' row of an empty period
    ]


# Built once per shape, with bound parameters: building the statement cost more than running it.
@lru_cache(maxsize=4)
def _stations_query(*, whole_months: bool, one_station: bool) -> Select[Any]:
    """The per-station sums of zone `zone`'s stored days `first` to `last`; with `whole_months`, the
    months `months_from` up to `months_until` from their sums and only the days before
    (`before_months`) and after from the days'; with `one_station`, station `station_id` only.
    Each row starts with `months_stored`: how many of those months have their sums stored."""
    parts = [_day_rows(bindparam("first"), bindparam("last"))]
    months_stored: ColumnElement[int] = literal(0)
    if whole_months:
        months_stored = select(func.count()).where(_months_stored()).scalar_subquery()
        # Three ranges apart: one OR would scan every day between them.
        months = _MONTH_STATION
        parts = [
            _day_rows(bindparam("first"), bindparam("before_months")),
            select(
                months.c.station_id, months.c.inspections.label("n"), months.c.compliant.label("ok")
            ).where(
                months.c.zone == bindparam("zone"),
                months.c.month >= bindparam("months_from"),
                months.c.month < bindparam("months_until"),
            ),
            _day_rows(bindparam("months_until"), bindparam("last")),
        ]
    if one_station:
        parts = [part.where(part.selected_columns.station_id == bindparam("station_id")) for part in parts]
    return with_facts(summed_by_station(union_all(*parts).subquery()), months_stored=months_stored)


def with_facts(rows: Select[Any], **facts: ColumnElement[Any]) -> Select[Any]:
    """The `facts` of a whole period (scalar subqueries, worked out once), then the columns of
    `rows`, on every row; one row of the facts alone (the rest null) when `rows` finds none. So a
    check and the counts it vouches for cost one round trip."""
    found = rows.subquery()
    known = select(*(fact.label(name) for name, fact in facts.items())).subquery()
    return select(known, found).select_from(known.outerjoin(found, true()))


def summed_by_station(rows: Subquery, *by: ColumnElement[Any]) -> Select[Any]:
    """The `n` and `ok` of `rows` summed per station (and per the columns `by` of `rows`): the `by`
    columns, station_id, the station's name, n, ok."""
    keys = [*by, rows.c.station_id]
    # Summed first, named after: the join meets one row per station, not a year of days.
    sums = (
        select(*keys, func.sum(rows.c.n).label("n"), func.sum(rows.c.ok).label("ok"))
        .group_by(*keys)
        .subquery()
    )
    named = [sums.c[key.name] for key in keys]
    return select(*named, Station.name, sums.c.n, sums.c.ok).outerjoin(
        Station, Station.id == sums.c.station_id
    )


def _day_rows(first: BindParameter[date], last: BindParameter[date]) -> Select[Any]:
    table = _DAY_STATION
    return select(table.c.station_id, table.c.inspections.label("n"), table.c.compliant.label("ok")).where(
        _in_period(bindparam("zone"), first, last)
    )


def _month_after(month: date) -> date:
    """The first day of the month after the one `month` falls in."""
    return (month.replace(day=28) + timedelta(days=4)).replace(day=1)


def _whole_months(first: date, last: date) -> list[date]:
    """The first days of the calendar months lying whole within `first` to `last`."""
    month = first if first.day == 1 else _month_after(first)
    months = []
    while _month_after(month) - timedelta(days=1) <= last:
        months.append(month)
        month = _month_after(month)
    return months


def _store_months(session: Session, name: str, months: list[date]) -> None:
    """Store the per-station sums of the months not stored yet, from their days' (all stored), once:
    the month's row is claimed like a day's, and only the transaction that inserted it sums it."""
    span = {"zone": name, "months_from": months[0], "months_until": _month_after(months[-1])}
    stored = set(session.scalars(_stored_months_query(), span))
    missing = [month for month in months if month not in stored]
    if not missing:
        return
    begin_write(session)
    for month in claim(
        session, _MONTH, [{"zone": name, "month": month} for month in missing], _MONTH.c.month
    ):
        days = _DAY_STATION
        sums = (
            select(
                literal(name, String),
                literal(month, Date),
                days.c.station_id,
                func.sum(days.c.inspections),
                func.sum(days.c.compliant),
            )
            .where(_in_period(name, month, _month_after(month) - timedelta(days=1)))
            .group_by(days.c.station_id)
        )
        columns = ["zone", "month", "station_id", "inspections", "compliant"]
        session.execute(_MONTH_STATION.insert().from_select(columns, sums))
    session.commit()


@lru_cache(maxsize=1)
def _stored_months_query() -> Select[Any]:
    """The months of zone `zone` from `months_from` up to `months_until` whose sums are stored."""
    return select(_MONTH.c.month).where(_months_stored())


def _months_stored() -> ColumnElement[bool]:
    """The stored months of zone `zone` from `months_from` up to `months_until` (bound parameters)."""
    month = _MONTH.c.month
    in_span = (month >= bindparam("months_from"), month < bindparam("months_until"))
    return and_(_MONTH.c.zone == bindparam("zone"), *in_span)


def _in_period(name: str | BindParameter[str], first: date | Any, last: date | Any) -> Any:
    """The per-station day rows of zone `name` from `first` to `last`, both included (values or
    bound parameters)."""
    table = _DAY_STATION
    return and_(table.c.zone == name, table.c.day >= first, table.c.day <= last)
