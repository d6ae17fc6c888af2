"""A station's scale: readings from a scale whose calibration lapsed are refused with a message that
says so and when; a reading above capacity is refused naming it; repeated readings that spread more
than allowed are refused (the scale had not settled); each inspection records the calibration in force."""

from __future__ import annotations

from datetime import UTC, date, datetime, timedelta
from decimal import Decimal
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session
from station_server import count_inspections, seed_study_vehicle

from app import config
from app.errors import InvalidInput
from app.inspections.models import Inspection
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import MeasuredCase, Rules, WheelReadings
from app.stations.details import StationDetails
from app.stations.models import Station
from app.stations.scale import ScaleRules
from app.stations.service import create_station

INSPECTIONS = "/api/v1/inspections"
TODAY = datetime.now(UTC).date()
STUDY: dict[str, Any] = {
    "registration_number": "BDG 252 QH",
    "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
}
CALIBRATED = StationDetails(
    location="Agbara, Ogun State",
    operator_contact="+234 803 555 0100",
    calibration_certificate="SON/CAL/2026/0415",
    calibration_valid_until=TODAY + timedelta(days=90),
    capacity_kg=Decimal("600"),
    division_kg=Decimal("0.5"),
)


def signed(client: TestClient, session: Session, **details: Any) -> TestClient:
    """The client signed as a new station whose scale has these details; the study's vehicle on file."""
    _station, key = create_station(session, name="Scale weighbridge", details=StationDetails(**details))
    seed_study_vehicle(session)
    client.headers["Authorization"] = f"Bearer {key}"
    return client


def readings(**changes: Any) -> dict[str, Any]:
    return {**STUDY, "readings": {**STUDY["readings"], **changes}}


def test_a_station_whose_calibration_lapsed_is_refused_saying_so_and_when(
    client: TestClient, session: Session
) -> None:
    api = signed(
        client,
        session,
        calibration_certificate="SON/CAL/2025/0099",
        calibration_valid_until=date(2026, 10, 31),
    )
    response = api.post(INSPECTIONS, json=STUDY)

    assert response.status_code == 403
    detail = response.json()["detail"]
    assert "calibration of this station's scale lapsed on 2026-11-01" in detail
    assert "SON/CAL/2025/0099 was valid until 2026-10-31" in detail
    assert response.json()["errors"][0]["rule"] == "calibration_lapsed"
    assert count_inspections(session) == 0


def test_a_calibration_valid_until_today_is_still_in_force(client: TestClient, session: Session) -> None:
    api = signed(client, session, calibration_certificate="C-1", calibration_valid_until=TODAY)
    assert api.post(INSPECTIONS, json=STUDY).status_code == 201


def test_each_inspection_records_the_calibration_in_force(client: TestClient, session: Session) -> None:
    api = signed(client, session, **vars(CALIBRATED))
    body = api.post(INSPECTIONS, json=STUDY).json()

    assert body["calibration"] == {
        "certificate": "SON/CAL/2026/0415",
        "valid_until": CALIBRATED.calibration_valid_until.isoformat(),  # type: ignore[union-attr]
    }
    station = session.scalars(select(Station)).one()
    station.calibration_certificate = "SON/CAL/2027/0001"
    station.calibration_valid_until = TODAY + timedelta(days=400)
    session.commit()
    stored = api.get(f"{INSPECTIONS}/{body['id']}").json()
    assert stored["calibration"]["certificate"] == "SON/CAL/2026/0415", "kept as it was when weighed"
    inspection = session.get(Inspection, body["id"])
    assert inspection is not None
    assert inspection.calibration_certificate == "SON/CAL/2026/0415"


def test_a_station_without_a_calibration_on_record_is_accepted_unless_required(
    client: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    api = signed(client, session)
    first = api.post(INSPECTIONS, json=STUDY)
    assert first.status_code == 201
    assert first.json()["calibration"] is None

    monkeypatch.setenv("TRIKECERT_REQUIRE_CALIBRATION", "true")
    config.get_settings.cache_clear()
    try:
        refused = api.post(INSPECTIONS, json=STUDY)
    finally:
        monkeypatch.undo()
        config.get_settings.cache_clear()
    assert refused.status_code == 403
    assert refused.json()["errors"][0]["rule"] == "calibration_missing"


@pytest.mark.parametrize(
    ("changes", "field"),
    [
        ({"front_kg": 620, "overall_kg": 870}, "readings.front_kg"),
        ({"overall_kg": [359, 601]}, "readings.overall_kg[1]"),
    ],
)
def test_a_reading_above_the_scale_capacity_is_refused_naming_it(
    client: TestClient, session: Session, changes: dict[str, Any], field: str
) -> None:
    api = signed(client, session, capacity_kg=Decimal("600"), division_kg=Decimal("0.5"))
    response = api.post(INSPECTIONS, json=readings(**changes))

    assert response.status_code == 422
    problem = response.json()["errors"][0]
    assert (problem["field"], problem["rule"]) == (field, "capacity")
    assert "above the 600 kg capacity" in problem["message"]
    assert count_inspections(session) == 0


def test_repeated_readings_that_spread_too_far_are_refused_naming_the_wheel(
    client: TestClient, session: Session
) -> None:
    api = signed(client, session)
    response = api.post(INSPECTIONS, json=readings(left_rear_kg=[113, 115.5, 116.5], overall_kg=None))

    assert response.status_code == 422
    problem = response.json()["errors"][0]
    assert (problem["field"], problem["rule"]) == ("readings.left_rear_kg", "spread")
    assert "the left rear wheel range from 113 to 116.5 kg, a spread of 3.5 kg" in problem["message"]
    assert "more than the allowed 2 kg" in problem["message"]
    assert "the scale had not settled" in problem["message"]
    assert count_inspections(session) == 0


def test_the_spread_is_reported_and_a_settled_set_is_kept_reading_by_reading(
    client: TestClient, session: Session
) -> None:
    api = signed(client, session)
    body = api.post(INSPECTIONS, json=readings(front_kg=[107, 108, 109], overall_kg=[358.5, 359.5])).json()

    assert body["spread_kg"] == {
        "front_kg": 2.0,
        "left_rear_kg": 0.0,
        "right_rear_kg": 0.0,
        "overall_kg": 1.0,
    }
    assert body["raw_readings"]["front_kg"] == [107.0, 108.0, 109.0]
    assert body["readings"]["front_kg"] == 108.0


def test_a_coarse_scale_may_spread_one_division(client: TestClient, session: Session) -> None:
    api = signed(client, session, capacity_kg=Decimal("3000"), division_kg=Decimal("5"))
    assert api.post(INSPECTIONS, json=readings(front_kg=[105, 110], overall_kg=None)).status_code == 201
    refused = api.post(INSPECTIONS, json=readings(front_kg=[105, 115], overall_kg=None))
    assert refused.status_code == 422
    assert "allowed 5 kg" in refused.json()["detail"]


def test_the_spread_limit_is_a_setting(
    client: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    api = signed(client, session)
    monkeypatch.setenv("TRIKECERT_MAX_READING_SPREAD_KG", "0.5")
    config.get_settings.cache_clear()
    try:
        response = api.post(INSPECTIONS, json=readings(front_kg=[108, 109], overall_kg=None))
    finally:
        monkeypatch.undo()
        config.get_settings.cache_clear()
    assert response.status_code == 422
    assert "allowed 0.5 kg" in response.json()["detail"]


def test_a_measured_case_that_had_not_settled_is_named(session: Session) -> None:
    seed_study_vehicle(session)
    unsettled = WheelReadings((Decimal(130), Decimal(134)), (Decimal(150),), (Decimal(167),))
    request = InspectionRequest(
        registration_number="BDG 252 QH",
        readings=WheelReadings((Decimal(108),), (Decimal(115),), (Decimal(135),)),
        measured_cases=(MeasuredCase(1, unsettled),),
    )
    with pytest.raises(InvalidInput, match=r"measured_cases\[0\]\.readings\.front_kg: .* the front wheel"):
        record_inspection(session, request=request, rules=Rules(), scale_rules=ScaleRules())


@pytest.fixture
def no_station_session(session: Session) -> Session:
    seed_study_vehicle(session)
    return session


def test_an_officers_weighing_has_no_calibration_and_still_must_settle(no_station_session: Session) -> None:
    settled = InspectionRequest(
        registration_number="BDG 252 QH",
        readings=WheelReadings((Decimal(108), Decimal(109)), (Decimal(115),), (Decimal(135),)),
    )
    inspection = record_inspection(no_station_session, request=settled, rules=Rules())
    assert inspection.calibration_certificate is None
    assert inspection.calibration_valid_until is None

    unsettled = InspectionRequest(
        registration_number="BDG 252 QH",
        readings=WheelReadings((Decimal(100), Decimal(109)), (Decimal(115),), (Decimal(135),)),
    )
    with pytest.raises(InvalidInput, match="the scale had not settled"):
        record_inspection(no_station_session, request=unsettled, rules=Rules())
