"""Counts per local day and per station: the zone decides the day, empty days are listed, the station
filter holds, certificates are counted when issued and revoked."""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, date, datetime
from decimal import Decimal
from zoneinfo import ZoneInfo

import pytest
from sqlalchemy.orm import Session

from app.inspections.service import InspectionRequest, record_inspection
from app.stability import Rules, WheelReadings
from app.stations.models import Station
from app.stations.service import create_station
from app.statistics.service import Counts, DayCounts, Period, daily_counts, station_counts, statistics
from app.vehicles.service import register_vehicle

LAGOS = ZoneInfo("Africa/Lagos")  # UTC+1 all year
NEW_YORK = ZoneInfo("America/New_York")  # UTC-5, UTC-4 from 8 March 2026
KOLKATA = ZoneInfo("Asia/Kolkata")  # UTC+5:30
SEATS = [("driver", Decimal("0.9303"))] + [("passenger", Decimal("1.6303"))] * 3


@pytest.fixture
def vehicle(session: Session) -> str:
    register_vehicle(
        session,
        registration_number="BDG 252 QH",
        make="Bajaj",
        model="RE",
        wheelbase_m=Decimal("2"),
        seats=SEATS,
    )
    return "BDG 252 QH"


Inspect = Callable[..., None]


@pytest.fixture
def inspect(backdate: Callable[..., None]) -> Inspect:
    """Store an inspection of the study's vehicle as if made at `at` (front 250 kg complies, 108 fails)."""

    def store(session: Session, *, at: datetime, compliant: bool, station: Station | None = None) -> None:
        front = Decimal("250") if compliant else Decimal("108")
        readings = WheelReadings((front,), (Decimal("115"),), (Decimal("135"),))
        request = InspectionRequest(registration_number="BDG 252 QH", readings=readings)
        stored = record_inspection(session, request=request, rules=Rules(), station=station)
        assert stored.compliant is compliant
        session.commit()
        backdate(stored.id, at)

    return store


def utc(year: int, month: int, day: int, hour: int, minute: int) -> datetime:
    return datetime(year, month, day, hour, minute, tzinfo=UTC)


@pytest.mark.usefixtures("vehicle")
def test_an_inspection_late_in_the_utc_day_counts_on_the_next_local_day(
    session: Session, inspect: Inspect
) -> None:
    inspect(session, at=utc(2026, 11, 9, 22, 59), compliant=True)  # 23:59 in Lagos, 9 November
    inspect(session, at=utc(2026, 11, 9, 23, 0), compliant=False)  # 00:00 in Lagos, 10 November
    inspect(session, at=utc(2026, 11, 10, 12, 0), compliant=False)

    days = daily_counts(session, period=Period(date(2026, 11, 8), date(2026, 11, 11)), zone=LAGOS)

    assert days == [
        DayCounts(date(2026, 11, 8), Counts(0, 0)),
        DayCounts(date(2026, 11, 9), Counts(1, 1)),
        DayCounts(date(2026, 11, 10), Counts(2, 0)),
        DayCounts(date(2026, 11, 11), Counts(0, 0)),
    ]


@pytest.mark.parametrize(
    ("zone", "at", "local_day"),
    [
        (LAGOS, utc(2026, 3, 8, 23, 30), date(2026, 3, 9)),
        (NEW_YORK, utc(2026, 3, 8, 3, 30), date(2026, 3, 7)),  # 22:30 EST, before the change
        (NEW_YORK, utc(2026, 3, 9, 3, 30), date(2026, 3, 8)),  # 23:30 EDT, after it
        (NEW_YORK, utc(2026, 3, 9, 4, 15), date(2026, 3, 9)),  # 00:15 EDT
        (KOLKATA, utc(2026, 3, 8, 18, 29), date(2026, 3, 8)),  # 23:59 IST
        (KOLKATA, utc(2026, 3, 8, 18, 30), date(2026, 3, 9)),  # 00:00 IST
    ],
)
@pytest.mark.usefixtures("vehicle")
def test_the_local_day_follows_the_zone_with_its_daylight_saving_and_half_hours(
    session: Session, inspect: Inspect, zone: ZoneInfo, at: datetime, local_day: date
) -> None:
    inspect(session, at=at, compliant=True)

    days = daily_counts(session, period=Period(date(2026, 3, 6), date(2026, 3, 10)), zone=zone)

    assert [d.day for d in days if d.counts.inspections] == [local_day]


@pytest.mark.usefixtures("vehicle")
def test_outside_the_period_nothing_counts(session: Session, inspect: Inspect) -> None:
    inspect(session, at=utc(2026, 11, 7, 22, 59), compliant=True)  # 7 November in Lagos
    inspect(session, at=utc(2026, 11, 11, 23, 0), compliant=True)  # 12 November in Lagos

    stats = statistics(session, period=Period(date(2026, 11, 8), date(2026, 11, 11)), zone=LAGOS)

    assert stats.total == Counts(0, 0)
    assert stats.stations == []


@pytest.mark.usefixtures("vehicle")
def test_counts_per_station_busiest_first_and_the_station_filter(session: Session, inspect: Inspect) -> None:
    agbara, _ = create_station(session, name="Agbara weighbridge")
    ikeja, _ = create_station(session, name="Ikeja weighbridge")
    noon = utc(2026, 11, 10, 12, 0)
    for compliant in (True, False, False):
        inspect(session, at=noon, compliant=compliant, station=ikeja)
    inspect(session, at=noon, compliant=True, station=agbara)
    inspect(session, at=noon, compliant=False)  # an officer in the pages
    period = Period(date(2026, 11, 10), date(2026, 11, 10))

    rows = [(s.station, s.counts) for s in station_counts(session, period=period, zone=LAGOS)]
    only_agbara = statistics(session, period=period, zone=LAGOS, station_id=agbara.id)

    assert rows[0] == ("Ikeja weighbridge", Counts(3, 1))
    assert sorted(rows[1:], key=str) == sorted(
        [("Agbara weighbridge", Counts(1, 1)), (None, Counts(1, 0))], key=str
    )
    assert only_agbara.total == Counts(1, 1)
    assert only_agbara.total.compliant_percent == 100.0
    assert Counts(3, 1).not_compliant == 2
    assert Counts().compliant_percent is None
