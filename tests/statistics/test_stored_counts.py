"""The stored counts of closed days: the statistics agree exactly with a full count of the records,
whether a day is read from its stored counts or counted live, across midnight in the display zone,
across a change of that zone (half-hour offsets and daylight saving), under concurrent requests,
and when a day's bounds change under a new tzdata."""

from __future__ import annotations

import threading
from collections.abc import Callable
from datetime import UTC, date, datetime, timedelta, tzinfo
from decimal import Decimal
from typing import TypeVar
from zoneinfo import ZoneInfo

import pytest
from sqlalchemy import Engine, func, select, update
from sqlalchemy.orm import Session

from app import db
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, revoke_certificate
from app.config import get_settings
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import Rules, WheelReadings
from app.stations.models import Station
from app.stations.service import create_station
from app.statistics.hours import store_hours
from app.statistics.models import (
    StatisticsDay,
    StatisticsDayStation,
    StatisticsHour,
    StatisticsHourStation,
    StatisticsMonth,
    StatisticsMonthStation,
)
from app.statistics.service import (
    Period,
    Statistics,
    certificate_counts,
    daily_counts,
    station_counts,
    statistics,
)
from app.statistics.stored import count_closed_days, zone_name
from app.vehicles.service import register_vehicle

LAGOS = ZoneInfo("Africa/Lagos")  # UTC+1 all year
NEW_YORK = ZoneInfo("America/New_York")  # UTC-5, UTC-4 from 8 March 2026
KOLKATA = ZoneInfo("Asia/Kolkata")  # UTC+5:30
SEATS = [("driver", Decimal("0.9303"))] + [("passenger", Decimal("1.6303"))] * 3
PERIOD = Period(date(2026, 3, 4), date(2026, 3, 12))
AFTER_THE_PERIOD = datetime(2026, 3, 20, tzinfo=UTC)

Store = Callable[..., int]
T = TypeVar("T")


@pytest.fixture
def store(session: Session, backdate: Callable[..., None]) -> Store:
    """Store an inspection as if made at `at` (front 250 kg complies, 108 fails); its id."""
    register_vehicle(
        session,
        registration_number="BDG 252 QH",
        make="Bajaj",
        model="RE",
        wheelbase_m=Decimal("2"),
        seats=SEATS,
    )

    def inspect(at: datetime, *, compliant: bool, station: Station | None = None) -> int:
        front = Decimal("250") if compliant else Decimal("108")
        readings = WheelReadings((front,), (Decimal("115"),), (Decimal("135"),))
        request = InspectionRequest(registration_number="BDG 252 QH", readings=readings)
        stored = record_inspection(session, request=request, rules=Rules(), station=station)
        session.commit()
        backdate(stored.id, at)
        return stored.id

    return inspect


def at(day: int, hour: int, minute: int = 0) -> datetime:
    return datetime(2026, 3, day, hour, minute, tzinfo=UTC)


@pytest.fixture
def history(session: Session, store: Store) -> list[int]:
    """Inspections at two stations and in the pages, on the edges of local days in every zone
    tested (hour and half-hour boundaries, the night New York moves its clocks), and certificates
    issued and revoked on such edges."""
    agbara, _ = create_station(session, name="Agbara weighbridge")
    ikeja, _ = create_station(session, name="Ikeja weighbridge")
    moments = [
        at(4, 12),
        at(5, 4, 59),  # 23:59 in New York, 10:29 in Kolkata
        at(5, 5, 0),  # 00:00 in New York
        at(5, 18, 29),  # 23:59 in Kolkata
        at(5, 18, 30),  # 00:00 in Kolkata
        at(6, 22, 59),  # 23:59 in Lagos
        at(6, 23, 0),  # 00:00 in Lagos
        at(8, 6, 59),  # 02:59 EDT, just after New York's change
        at(8, 7, 30),
        at(9, 3, 59),  # 23:59 EDT
        at(9, 4, 0),  # 00:00 EDT
        at(11, 23, 45),
        at(12, 13, 15),
    ]
    # Each document is issued before the vehicle is weighed again: the records refuse a certificate
    # for a weighing that a later one contradicts.
    issued_at = {4: at(5, 18, 31), 5: at(6, 22, 59), 9: at(9, 4, 0)}
    actor, settings = Actor.of_cli(), get_settings()
    ids, issued = [], {}
    for i, moment in enumerate(moments):
        station = (agbara, ikeja, None)[i % 3]
        ids.append(store(moment, compliant=i % 4 != 1, station=station))
        if i in issued_at:
            issued[i] = issue_certificate(
                session, inspection_id=ids[i], actor=actor, settings=settings, now=issued_at[i]
            )
    first = issued[4]
    admin = Actor("admin", admin=True)
    revoke_certificate(
        session, number=first.certificate.number, actor=admin, reason="Wrong", now=at(6, 23, 0)
    )
    return ids


def full_count(session: Session, period: Period, zone: tzinfo, station_id: int | None = None) -> Statistics:
    """The period's counts taken from the records alone, every day live."""
    days = daily_counts(session, period=period, zone=zone, station_id=station_id)
    stations = station_counts(session, period=period, zone=zone, station_id=station_id)
    issued, refusals, revoked = certificate_counts(session, period=period, zone=zone)
    total = days[0].counts
    for day in days[1:]:
        total += day.counts
    return Statistics(period, total, days, stations, issued, refusals, revoked)


def same(found: Statistics, expected: Statistics) -> None:
    assert found.days == expected.days
    assert found.total == expected.total
    assert sorted(found.stations, key=str) == sorted(expected.stations, key=str)
    counts = (found.certificates_issued, found.refusals_issued, found.certificates_revoked)
    assert counts == (expected.certificates_issued, expected.refusals_issued, expected.certificates_revoked)


def together(visit: Callable[[Session], T], times: int = 4) -> list[T]:
    """What `visit` returns when run at once in `times` threads, each with a session of its own."""
    start = threading.Barrier(times)
    results: list[T] = []

    def run() -> None:
        with db.get_sessionmaker()() as own:
            start.wait()
            results.append(visit(own))

    threads = [threading.Thread(target=run) for _ in range(times)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return results


def stored_days(session: Session, zone: tzinfo) -> int:
    return session.scalar(select(func.count()).where(StatisticsDay.zone == zone_name(zone))) or 0


@pytest.mark.parametrize("zone", [LAGOS, NEW_YORK, KOLKATA, UTC], ids=str)
@pytest.mark.usefixtures("history")
def test_stored_counts_agree_with_a_full_count(session: Session, zone: tzinfo) -> None:
    expected = full_count(session, PERIOD, zone)
    assert expected.total.inspections > 0

    first_visit = statistics(session, period=PERIOD, zone=zone, now=AFTER_THE_PERIOD)
    second_visit = statistics(session, period=PERIOD, zone=zone, now=AFTER_THE_PERIOD)

    same(first_visit, expected)
    same(second_visit, expected)
    assert stored_days(session, zone) == PERIOD.days, "every closed day stored once, empty ones too"
    recounted = count_closed_days(session, zone=zone, first=PERIOD.first, last=PERIOD.last)
    assert recounted == 0, "each stored day's bounds read back as the zone's: none counted again"
    assert first_visit.certificates_issued + first_visit.refusals_issued == 3
    assert first_visit.certificates_revoked == 1


@pytest.mark.usefixtures("history")
def test_the_station_filter_reads_the_same_stored_days(session: Session) -> None:
    statistics(session, period=PERIOD, zone=KOLKATA, now=AFTER_THE_PERIOD)  # stores every day
    for station in session.scalars(select(Station)):
        expected = full_count(session, PERIOD, KOLKATA, station_id=station.id)

        found = statistics(session, period=PERIOD, zone=KOLKATA, station_id=station.id, now=AFTER_THE_PERIOD)

        same(found, expected)
        assert [s.station for s in found.stations] == [station.name]


def test_across_midnight_in_the_display_zone(session: Session, store: Store) -> None:
    store(at(6, 22, 50), compliant=True)  # 23:50 on 6 March in Lagos
    store(at(6, 23, 10), compliant=False)  # 00:10 on 7 March
    period = Period(date(2026, 3, 5), date(2026, 3, 7))

    just_after_midnight = statistics(session, period=period, zone=LAGOS, now=at(6, 23, 30))
    assert stored_days(session, LAGOS) == 1, "6 March is not closed until an hour after midnight"
    same(just_after_midnight, full_count(session, period, LAGOS))

    later = statistics(session, period=period, zone=LAGOS, now=at(7, 0, 30))
    assert stored_days(session, LAGOS) == 2, "6 March closed at 01:00 in Lagos"
    same(later, full_count(session, period, LAGOS))

    store(at(7, 0, 40), compliant=True)  # today in Lagos, after 6 March was stored
    today_grows = statistics(session, period=period, zone=LAGOS, now=at(7, 0, 45))
    same(today_grows, full_count(session, period, LAGOS))
    assert [d.counts.inspections for d in today_grows.days] == [0, 1, 2]


@pytest.mark.usefixtures("history")
def test_across_a_change_of_zone(session: Session) -> None:
    for zone in (LAGOS, KOLKATA, NEW_YORK, LAGOS):
        found = statistics(session, period=PERIOD, zone=zone, now=AFTER_THE_PERIOD)

        same(found, full_count(session, PERIOD, zone))
    assert len(session.scalars(select(StatisticsDay.zone).distinct()).all()) == 3, "one set of days per zone"


@pytest.mark.usefixtures("history")
def test_concurrent_requests_store_each_day_once(engine: Engine, session: Session) -> None:
    counted = together(
        lambda own: count_closed_days(own, zone=NEW_YORK, first=PERIOD.first, last=PERIOD.last)
    )

    assert sum(counted) == PERIOD.days
    same(
        statistics(session, period=PERIOD, zone=NEW_YORK, now=AFTER_THE_PERIOD),
        full_count(session, PERIOD, NEW_YORK),
    )


@pytest.mark.usefixtures("history")
def test_a_day_counted_over_other_bounds_is_counted_again(session: Session, owner_engine: Engine) -> None:
    statistics(session, period=PERIOD, zone=LAGOS, now=AFTER_THE_PERIOD)
    day = date(2026, 3, 6)
    with owner_engine.begin() as connection:  # as if the zone's rules had changed since it was counted
        connection.execute(
            update(StatisticsDay)
            .where(StatisticsDay.day == day)
            .values(starts_at=at(5, 22), certificates_issued=99)
        )
        connection.execute(
            update(StatisticsDayStation).where(StatisticsDayStation.day == day).values(inspections=99)
        )

    found = statistics(session, period=PERIOD, zone=LAGOS, now=AFTER_THE_PERIOD)

    same(found, full_count(session, PERIOD, LAGOS))


def test_the_nightly_command_stores_the_closed_days(
    session: Session, store: Store, capsys: pytest.CaptureFixture[str]
) -> None:
    from app.cli import main as trikecert
    from app.db import utcnow

    store(utcnow() - timedelta(days=3), compliant=True)

    assert trikecert(["count-statistics", "--days", "5"]) == 0
    assert "counted 5 closed day(s)" in capsys.readouterr().out
    assert trikecert(["count-statistics", "--days", "5"]) == 0
    assert "counted 0 closed day(s)" in capsys.readouterr().out, "stored once"

    today = datetime.now(UTC).date()
    period = Period(today - timedelta(days=6), today)
    same(statistics(session, period=period, zone=UTC), full_count(session, period, UTC))
    assert statistics(session, period=period, zone=UTC).total.inspections == 1


# Months: inspections from January to April 2026 on the edges of months in each zone tested.
MONTH_EDGES = [
    datetime(2026, 1, 10, 12, tzinfo=UTC),
    datetime(2026, 1, 31, 18, 29, tzinfo=UTC),  # 31 January in Kolkata, 23:59
    datetime(2026, 1, 31, 18, 30, tzinfo=UTC),  # 1 February in Kolkata
    datetime(2026, 1, 31, 23, 0, tzinfo=UTC),  # 1 February in Lagos
    datetime(2026, 2, 1, 4, 59, tzinfo=UTC),  # 31 January in New York
    datetime(2026, 2, 14, 9, tzinfo=UTC),
    datetime(2026, 2, 28, 23, 30, tzinfo=UTC),  # 1 March in Lagos, 28 February in UTC
    datetime(2026, 3, 1, 5, 0, tzinfo=UTC),  # 1 March in New York
    datetime(2026, 3, 15, 16, tzinfo=UTC),
    datetime(2026, 3, 31, 22, 59, tzinfo=UTC),  # 31 March in Lagos
    datetime(2026, 3, 31, 23, 0, tzinfo=UTC),  # 1 April in Lagos
    datetime(2026, 4, 9, 8, tzinfo=UTC),
]
MONTHS_PERIODS = [
    Period(date(2026, 1, 15), date(2026, 4, 10)),  # February and March whole, days at both ends
    Period(date(2026, 2, 1), date(2026, 3, 31)),  # two whole months, no day outside them
    Period(date(2026, 1, 1), date(2026, 2, 27)),  # January whole, February not
]
AFTER_THE_MONTHS = datetime(2026, 5, 2, tzinfo=UTC)


@pytest.fixture
def months_history(session: Session, store: Store) -> None:
    agbara, _ = create_station(session, name="Agbara weighbridge")
    ikeja, _ = create_station(session, name="Ikeja weighbridge")
    for i, moment in enumerate(MONTH_EDGES):
        store(moment, compliant=i % 3 != 1, station=(agbara, ikeja, None)[i % 3])


@pytest.mark.parametrize("zone", [LAGOS, NEW_YORK, KOLKATA, UTC], ids=str)
@pytest.mark.usefixtures("months_history")
def test_whole_months_are_summed_once_and_agree_with_a_full_count(session: Session, zone: tzinfo) -> None:
    for period in MONTHS_PERIODS:
        expected = full_count(session, period, zone)
        assert expected.total.inspections > 0
        same(statistics(session, period=period, zone=zone, now=AFTER_THE_MONTHS), expected)
        same(statistics(session, period=period, zone=zone, now=AFTER_THE_MONTHS), expected)
        for station in session.scalars(select(Station)):
            found = statistics(session, period=period, zone=zone, station_id=station.id, now=AFTER_THE_MONTHS)
            same(found, full_count(session, period, zone, station_id=station.id))
    months = session.scalars(select(StatisticsMonth.month).where(StatisticsMonth.zone == zone_name(zone)))
    assert sorted(months) == [date(2026, 1, 1), date(2026, 2, 1), date(2026, 3, 1)], "each stored once"


@pytest.mark.usefixtures("months_history")
def test_a_month_with_a_day_counted_again_is_summed_again(session: Session, owner_engine: Engine) -> None:
    period = MONTHS_PERIODS[0]
    statistics(session, period=period, zone=LAGOS, now=AFTER_THE_MONTHS)
    day = date(2026, 2, 14)
    with owner_engine.begin() as connection:  # as if the zone's rules had changed since it was counted
        connection.execute(update(StatisticsDay).where(StatisticsDay.day == day).values(starts_at=at(5, 22)))
        connection.execute(
            update(StatisticsMonthStation)
            .where(StatisticsMonthStation.month == date(2026, 2, 1))
            .values(inspections=99)
        )

    found = statistics(session, period=period, zone=LAGOS, now=AFTER_THE_MONTHS)

    same(found, full_count(session, period, LAGOS))


@pytest.mark.usefixtures("months_history")
def test_concurrent_visits_sum_each_month_once(session: Session) -> None:
    period = MONTHS_PERIODS[0]
    count_closed_days(session, zone=KOLKATA, first=period.first, last=period.last)
    found = together(lambda own: statistics(own, period=period, zone=KOLKATA, now=AFTER_THE_MONTHS))

    expected = full_count(session, period, KOLKATA)
    assert len(found) == 4
    for each in found:
        same(each, expected)
    month_rows = (
        select(func.count()).select_from(StatisticsMonth).where(StatisticsMonth.zone == zone_name(KOLKATA))
    )
    assert session.scalar(month_rows) == 2, "February and March, each stored once"
    same(statistics(session, period=period, zone=KOLKATA, now=AFTER_THE_MONTHS), expected)


# Hours: the open days' closed whole UTC hours are stored; the rest of the open days is counted live.
HOURS_MOMENTS = [
    at(8, 18, 29),  # 23:59 on 8 March in Kolkata
    at(8, 18, 30),  # 00:00 on 9 March in Kolkata
    at(8, 23, 0),  # 00:00 on 9 March in Lagos
    at(9, 0, 0),
    at(9, 3, 59),  # 23:59 on 8 March in New York (EDT)
    at(9, 4, 0),  # 00:00 on 9 March in New York
    at(9, 9, 59),
    at(9, 10, 0),
    at(9, 10, 1),
    at(9, 16, 45),
    at(9, 17, 59),  # in the last hour closed at 19:10
]


def hours_expected(zone: tzinfo, now: datetime) -> list[datetime]:
    """The whole UTC hours of the open days closed an hour before `now`, found hour by hour, apart
    from the service's arithmetic."""
    first_open = (now - timedelta(hours=1)).astimezone(zone).date()
    start = datetime.combine(first_open, datetime.min.time(), tzinfo=zone).astimezone(UTC)
    hour, whole = start.replace(minute=0, second=0, microsecond=0), []
    while hour + timedelta(hours=2) <= now:
        if hour >= start:
            whole.append(hour)
        hour += timedelta(hours=1)
    return whole


def stored_hours(session: Session) -> list[datetime]:
    return list(session.scalars(select(StatisticsHour.starts_at).order_by(StatisticsHour.starts_at)))


@pytest.mark.parametrize("zone", [LAGOS, NEW_YORK, KOLKATA, UTC], ids=str)
def test_the_open_days_closed_hours_are_stored_once_and_agree_with_a_full_count(
    session: Session, store: Store, zone: tzinfo
) -> None:
    agbara, _ = create_station(session, name="Agbara weighbridge")
    for i, moment in enumerate(HOURS_MOMENTS):
        store(moment, compliant=i % 3 != 1, station=(agbara, None)[i % 2])
    period = Period(date(2026, 3, 7), date(2026, 3, 10))
    now = at(9, 19, 10)

    first_visit = statistics(session, period=period, zone=zone, now=now)
    same(first_visit, full_count(session, period, zone))
    assert stored_hours(session) == hours_expected(zone, now)
    assert len(stored_hours(session)) > 10
    assert statistics(session, period=period, zone=zone, now=now) == first_visit
    assert stored_hours(session) == hours_expected(zone, now), "each hour stored once"

    store(at(9, 18, 50), compliant=True, station=agbara)  # committed late, in an hour not closed yet
    store(at(9, 19, 5), compliant=False)
    same(statistics(session, period=period, zone=zone, now=now), full_count(session, period, zone))

    an_hour_later = at(9, 20, 10)
    found = statistics(session, period=period, zone=zone, now=an_hour_later)
    same(found, full_count(session, period, zone))
    assert set(hours_expected(zone, an_hour_later)) <= set(stored_hours(session)), "closed at 20:00"
    for station in (agbara.id,):
        by_station = statistics(session, period=period, zone=zone, station_id=station, now=an_hour_later)
        same(by_station, full_count(session, period, zone, station_id=station))


@pytest.mark.parametrize("zone", [LAGOS, KOLKATA], ids=str)
def test_the_first_hour_after_midnight_two_open_days(session: Session, store: Store, zone: tzinfo) -> None:
    for i, moment in enumerate(HOURS_MOMENTS):
        store(moment, compliant=i % 2 == 0)
    local_midnight = datetime.combine(date(2026, 3, 10), datetime.min.time(), tzinfo=zone).astimezone(UTC)
    store(local_midnight - timedelta(minutes=20), compliant=True)  # yesterday, in the hour not closed
    store(local_midnight + timedelta(minutes=10), compliant=False)  # today
    period = Period(date(2026, 3, 8), date(2026, 3, 10))
    now = local_midnight + timedelta(minutes=40)

    found = statistics(session, period=period, zone=zone, now=now)

    same(found, full_count(session, period, zone))
    assert stored_hours(session) == hours_expected(zone, now)
    assert [d.counts.inspections for d in found.days][-1] == 1


@pytest.mark.usefixtures("history")
def test_hours_long_closed_are_pruned(session: Session) -> None:
    statistics(session, period=Period(date(2026, 3, 5), date(2026, 3, 6)), zone=UTC, now=at(6, 12))
    assert len(stored_hours(session)) == 11
    statistics(session, period=Period(date(2026, 3, 9), date(2026, 3, 9)), zone=UTC, now=at(9, 6))

    assert stored_hours(session)[0] == at(9, 0), (
        "the hours of 6 March pruned once the hours of 9 March are stored"
    )
    counted_hours = session.scalars(select(StatisticsHourStation.starts_at)).all()
    assert counted_hours, "9 March's hours 03:00 and 04:00 had inspections"
    assert min(counted_hours) >= at(9, 0), "and their per-station rows with them"


@pytest.mark.usefixtures("history")
def test_concurrent_visits_store_each_hour_once(session: Session) -> None:
    counted = together(lambda own: store_hours(own, at(6, 0), at(6, 23)))

    assert sorted(counted) == [0, 0, 0, 23]
    assert len(stored_hours(session)) == 23
    period = Period(date(2026, 3, 6), date(2026, 3, 6))
    same(statistics(session, period=period, zone=UTC, now=at(7, 0, 30)), full_count(session, period, UTC))
