"""The count a list shows beside its page (app/inspections/service.py, count_inspections): from the
stored counts of the closed days the period covers whole, and the records at its two ends, it is
exactly the count a full scan of the records gives, for every filter, at any time of day, whatever
the display zone, and with the days not stored yet or stored already."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator, Mapping
from datetime import UTC, datetime, timedelta
from decimal import Decimal
from typing import Any

import pytest
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app import config
from app.inspections.models import Inspection
from app.inspections.service import (
    InspectionFilter,
    InspectionRequest,
    count_inspections,
    list_inspections,
    record_inspection,
)
from app.stability import Rules, WheelReadings
from app.stations.models import Station
from app.stations.service import create_station
from app.statistics.models import StatisticsDay
from app.vehicles.models import Vehicle
from app.vehicles.service import register_vehicle

SEATS = [("driver", Decimal("0.9303"))] + [("passenger", Decimal("1.6303"))] * 3
# Ten days of March 2026, the hours chosen on the edges of local days in Lagos (UTC+1),
# New York (UTC-5, UTC-4 from 8 March) and Kolkata (UTC+5:30).
MOMENTS = [
    (day, hour, minute)
    for day in range(1, 11)
    for hour, minute in ((4, 59), (5, 0), (18, 29), (18, 30), (22, 59), (23, 0))
]
NOW = datetime(2026, 3, 20, 12, tzinfo=UTC)  # every day above closed


def moment(day: int, hour: int, minute: int = 0) -> datetime:
    return datetime(2026, 3, day, hour, minute, tzinfo=UTC)


def record(session: Session, registration: str, *, front: Decimal, station: Station | None) -> int:
    """Record an inspection of the vehicle (rear wheels 115 and 135 kg), uncommitted; its id."""
    readings = WheelReadings((front,), (Decimal("115"),), (Decimal("135"),))
    request = InspectionRequest(registration_number=registration, readings=readings)
    return record_inspection(session, request=request, rules=Rules(), station=station).id


def inspect(
    session: Session,
    backdate: Callable[..., None],
    registration: str,
    *,
    front: Decimal,
    station: Station | None,
    at: datetime,
) -> None:
    """Store an inspection of the vehicle (rear wheels 115 and 135 kg) as if made at `at`."""
    stored = record(session, registration, front=front, station=station)
    session.commit()
    backdate(stored, at)


@pytest.fixture
def history(session: Session, backdate_all: Callable[[Mapping[int, datetime]], None]) -> list[Station]:
    """Inspections at two stations and from the pages, compliant or not, on the day edges above
    (stored, then their times rewritten, all at once)."""
    register_vehicle(
        session,
        registration_number="BDG 252 QH",
        make="Bajaj",
        model="RE",
        wheelbase_m=Decimal(2),
        seats=SEATS,
    )
    stations = [create_station(session, name=name)[0] for name in ("Agbara weighbridge", "Ikeja weighbridge")]
    times = {}
    for i, (day, hour, minute) in enumerate(MOMENTS):
        front = Decimal("250") if i % 3 else Decimal("108")  # 250 kg at the front complies, 108 does not
        station = (stations[0], stations[1], None)[i % 3]
        times[record(session, "BDG 252 QH", front=front, station=station)] = moment(day, hour, minute)
    session.commit()
    backdate_all(times)
    return stations


@pytest.fixture(params=["Africa/Lagos", "America/New_York", "Asia/Kolkata", "UTC"])
def display_zone(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> Iterator[str]:
    """The display zone, whose days are stored for the counts."""
    monkeypatch.setenv("TRIKECERT_DISPLAY_TIMEZONE", request.param)
    config.get_settings.cache_clear()
    yield request.param
    config.get_settings.cache_clear()


def full_count(session: Session, where: InspectionFilter) -> int:
    """The records counted one by one, the reference."""
    query = select(func.count()).select_from(Inspection)
    if where.compliant is not None:
        query = query.where(Inspection.compliant == where.compliant)
    if where.station_id is not None:
        query = query.where(Inspection.station_id == where.station_id)
    if where.since is not None:
        query = query.where(Inspection.created_at >= where.since)
    if where.until is not None:
        query = query.where(Inspection.created_at < where.until)
    return int(session.scalar(query) or 0)


PERIODS: list[tuple[datetime | None, datetime | None]] = [
    (None, None),  # all time
    (datetime(1472, 8, 5, 18, 39, tzinfo=UTC), moment(4, 0, 0)),  # from long before the first inspection
    (moment(1, 0, 0), datetime(9999, 1, 1, tzinfo=UTC)),  # until long after now
    (None, datetime(9999, 12, 31, 23, 59, tzinfo=UTC)),  # until the last day a date holds (a 500 once)
    (moment(2, 22, 59), None),  # since a Lagos day edge
    (moment(3, 7, 13), moment(9, 17, 2)),  # odd times at both ends
    (moment(1, 0, 0), moment(13, 0, 0)),  # UTC midnights
    (moment(4, 18, 30), moment(9, 4, 0)),  # a Kolkata edge, then a New York one
    (moment(5, 5, 0), moment(6, 5, 0)),  # one day only
    (moment(10, 1, 0), None),  # since within the last day
]


def test_the_count_of_a_list_is_a_full_count(
    session: Session, history: list[Station], display_zone: str
) -> None:
    for (since, until), compliant, station in itertools.product(
        PERIODS, (None, True, False), (None, *history)
    ):
        where = InspectionFilter(
            compliant=compliant, station_id=station.id if station else None, since=since, until=until
        )
        expected = full_count(session, where)
        assert count_inspections(session, where=where, now=NOW) == expected, (where, display_zone)
        # Again: now from the days the first call stored.
        assert count_inspections(session, where=where, now=NOW) == expected, (where, display_zone)


def test_a_long_period_is_counted_from_stored_days_and_a_short_one_from_the_records(
    session: Session, history: list[Station], display_zone: str
) -> None:
    stored_days = select(func.count()).select_from(StatisticsDay).where(StatisticsDay.zone == display_zone)
    short = InspectionFilter(since=moment(5, 5, 0), until=moment(6, 5, 0))
    assert count_inspections(session, where=short, now=NOW) == full_count(session, short)
    assert session.scalar(stored_days) == 0, "a day or less: the records alone"

    long = InspectionFilter(since=moment(1, 12, 0), until=moment(10, 12, 0))
    assert count_inspections(session, where=long, now=NOW) == full_count(session, long)
    assert 7 <= (session.scalar(stored_days) or 0) <= 9, "the whole closed days in between, stored"


def test_no_day_before_the_first_inspection_is_stored(session: Session, history: list[Station]) -> None:
    where = InspectionFilter(since=datetime(1472, 8, 5, 18, 39, tzinfo=UTC))
    assert count_inspections(session, where=where, now=NOW) == full_count(session, where)
    first_stored = session.scalars(select(StatisticsDay.day).order_by(StatisticsDay.day)).first()
    assert first_stored is not None
    assert first_stored >= moment(1, 0, 0).date() - timedelta(days=1), "nothing from the fifteenth century"


def test_decades_of_history_are_stored_and_counted(
    session: Session, history: list[Station], backdate: Callable[..., None]
) -> None:
    """Thirty years of closed days in one request (years past any driver's limit on parameters in
    one statement) are stored and counted exactly."""
    oldest = session.scalars(select(Inspection.id).order_by(Inspection.id)).first()
    assert oldest is not None
    backdate(oldest, datetime(1996, 3, 1, 9, tzinfo=UTC))
    where = InspectionFilter(since=datetime(1990, 1, 1, tzinfo=UTC))
    assert count_inspections(session, where=where, now=NOW) == full_count(session, where) == len(MOMENTS)
    stored_days = select(func.count()).select_from(StatisticsDay)
    assert (session.scalar(stored_days) or 0) > 30 * 365


def test_days_not_closed_yet_are_counted_from_the_records(session: Session, history: list[Station]) -> None:
    where = InspectionFilter(since=moment(1, 0, 0))
    early = moment(10, 23, 30)  # 00:30 on 11 March in Lagos: 10 March is not closed yet
    assert count_inspections(session, where=where, now=early) == full_count(session, where)
    last_stored = session.scalars(select(StatisticsDay.day).order_by(StatisticsDay.day.desc())).first()
    assert last_stored == moment(9, 0, 0).date(), "the last day stored is the last closed one"
    later = early + timedelta(days=2)
    assert count_inspections(session, where=where, now=later) == full_count(session, where)


def test_pages_follow_each_other_newest_first_with_their_vehicle_and_station(
    session: Session, history: list[Station], backdate: Callable[..., None]
) -> None:
    """Pages of seven, read one after the other, are every matching inspection once, newest first
    (equal times by id, the later first), each with its own vehicle and station."""
    register_vehicle(
        session,
        registration_number="KJA 19 XY",
        make="TVS",
        model="King",
        wheelbase_m=Decimal(2),
        seats=SEATS,
    )
    for day in (2, 6):  # at the same moment as one of the other vehicle's
        inspect(
            session, backdate, "KJA 19 XY", front=Decimal("250"), station=history[1], at=moment(day, 5, 0)
        )
    names = {station.id: station.name for station in history}
    everything = session.execute(
        select(Inspection.id, Vehicle.registration_number, Inspection.station_id, Inspection.compliant)
        .join(Vehicle, Vehicle.id == Inspection.vehicle_id)
        .order_by(Inspection.created_at.desc(), Inspection.id.desc())
    ).all()
    filters: list[tuple[InspectionFilter, Callable[[Any], bool]]] = [
        (InspectionFilter(), lambda row: True),
        (InspectionFilter(compliant=False), lambda row: not row.compliant),
        (InspectionFilter(station_id=history[1].id), lambda row: row.station_id == history[1].id),
        (InspectionFilter(registration_number="kja19xy"), lambda row: row.registration_number == "KJA 19 XY"),
        (
            InspectionFilter(registration_number="BDG 252 QH"),
            lambda row: row.registration_number == "BDG 252 QH",
        ),
    ]
    for where, matches in filters:
        expected = [
            (row.id, row.registration_number, names.get(row.station_id)) for row in everything if matches(row)
        ]
        listed: list[tuple[int, str, str | None]] = []
        for offset in range(0, len(expected) + 7, 7):
            page, count = list_inspections(session, where=where, limit=7, offset=offset)
            assert count == len(expected), where
            listed += [(item.id, item.registration_number, item.station_name) for item in page]
        assert listed == expected, where
