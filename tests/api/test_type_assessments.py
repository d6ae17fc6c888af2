"""Type assessments through the station API: the study's three vehicles reproduce section 7 to the digit."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session
from study_data import STUDY_TYPE_READINGS, STUDY_TYPE_SPREAD, STUDY_TYPE_TABLE, STUDY_VEHICLE

from app.audit.models import AuditEvent
from app.stations.service import create_station

STUDY_MODEL = {"make": "Bajaj", "model": "RE", "model_year": 2012}


def register_and_weigh(api: TestClient, registration: str, readings: dict[str, Any], **vehicle: Any) -> int:
    """Register a vehicle of the study's model (unless it is on file) and weigh it; the inspection id."""
    body = {**STUDY_VEHICLE, "registration_number": registration, **vehicle}
    registered = api.post("/api/v1/vehicles", json=body)
    assert registered.status_code in (201, 409), registered.text
    weighed = api.post(
        "/api/v1/inspections", json={"registration_number": registration, "readings": readings}
    )
    assert weighed.status_code == 201, weighed.text
    return int(weighed.json()["id"])


@pytest.fixture
def study_fleet(api: TestClient) -> dict[str, int]:
    """The three study vehicles weighed with section 7's readings: registration -> inspection id."""
    return {reg: register_and_weigh(api, reg, readings) for reg, readings in STUDY_TYPE_READINGS.items()}


def problem(response: Any) -> tuple[str, str]:
    error = response.json()["errors"][0]
    return error["field"], error["rule"]


def test_the_study_vehicles_reproduce_the_types_table_4_and_spread_to_the_digit(
    api: TestClient, study_fleet: dict[str, int], session: Session
) -> None:
    response = api.post("/api/v1/type-assessments", json=STUDY_MODEL)
    assert response.status_code == 201, response.text
    body = response.json()
    assert set(body) == {"id", "vehicles", "table", "spread", "compliant", "max_compliant_occupants"}
    table = [
        (r["occupants"], r["total_kg"], r["rear_kg"], r["lsf"], r["variance"], r["compliant"])
        for r in body["table"]
    ]
    assert table == STUDY_TYPE_TABLE
    spread = [
        (
            s["occupants"],
            s["min_lsf"],
            s["mean_lsf"],
            s["max_lsf"],
            s["sd_lsf"],
            s["upper_95_lsf"],
            s["confident_compliant"],
        )
        for s in body["spread"]
    ]
    assert spread == STUDY_TYPE_SPREAD
    assert body["compliant"] is False
    assert body["max_compliant_occupants"] == 1
    vehicles = {v["registration_number"]: v for v in body["vehicles"]}
    assert {reg: v["inspection_id"] for reg, v in vehicles.items()} == study_fleet
    bdg = vehicles["BDG 252 QH"]["cases"]
    assert [(c["occupants"], c["lsf"], c["compliant"]) for c in bdg[:2]] == [
        (0, 0.70028, False),
        (1, 0.66082, True),
    ]

    stored = api.get(f"/api/v1/type-assessments/{body['id']}")
    assert stored.status_code == 200
    assert stored.json() == body
    event = session.scalars(select(AuditEvent).where(AuditEvent.target_type == "type_assessment")).one()
    assert event.action == "type_assessment.created"
    assert event.target_id == str(body["id"])


def test_without_ids_the_latest_inspection_of_each_vehicle_is_used_and_chosen_ids_override_it(
    api: TestClient, study_fleet: dict[str, int]
) -> None:
    later = register_and_weigh(
        api, "AGL 7180", {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359}
    )
    latest = api.post("/api/v1/type-assessments", json={"make": "bajaj", "model": " re "}).json()
    assert sorted(v["inspection_id"] for v in latest["vehicles"]) == sorted(
        [study_fleet["BDG 252 QH"], study_fleet["AGL 532 QH"], later]
    )
    assert latest["spread"][0]["mean_lsf"] != STUDY_TYPE_SPREAD[0][2]

    chosen = api.post(
        "/api/v1/type-assessments", json={**STUDY_MODEL, "inspection_ids": list(study_fleet.values())}
    )
    assert chosen.status_code == 201, chosen.text
    assert [v["inspection_id"] for v in chosen.json()["vehicles"]] == list(study_fleet.values())
    assert chosen.json()["spread"][0]["mean_lsf"] == STUDY_TYPE_SPREAD[0][2]


def test_two_identical_vehicles_have_no_spread(api: TestClient) -> None:
    readings = {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359}
    for registration in ("TWIN 1", "TWIN 2"):
        register_and_weigh(api, registration, readings, model="Twin")
    body = api.post("/api/v1/type-assessments", json={"make": "Bajaj", "model": "Twin"}).json()
    for row, case in zip(body["table"], body["spread"], strict=True):
        assert case["sd_lsf"] == 0
        assert case["min_lsf"] == case["mean_lsf"] == case["max_lsf"] == case["upper_95_lsf"]
        assert case["confident_compliant"] is row["compliant"]
    assert body["max_compliant_occupants"] == 1


def test_a_model_with_one_vehicle_is_refused_naming_the_field(
    api: TestClient, study_fleet: dict[str, int]
) -> None:
    response = api.post("/api/v1/type-assessments", json={"make": "Bajaj", "model": "RE", "model_year": 2099})
    assert response.status_code == 422
    assert problem(response) == ("model", "too_few")
    response = api.post("/api/v1/type-assessments", json={**STUDY_MODEL, "inspection_ids": [1]})
    assert response.status_code == 422
    assert problem(response)[0] == "inspection_ids"


def test_different_seat_layouts_are_refused_naming_both_vehicles(
    api: TestClient, study_fleet: dict[str, int]
) -> None:
    readings = {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359}
    register_and_weigh(api, "KJA 1 AA", readings, seats=STUDY_VEHICLE["seats"][:3])
    response = api.post("/api/v1/type-assessments", json=STUDY_MODEL)
    assert response.status_code == 422
    assert problem(response) == ("inspection_ids", "same_layout")
    message = response.json()["errors"][0]["message"]
    assert "KJA 1 AA" in message
    assert "seat layout" in message
    assert any(reg in message for reg in STUDY_TYPE_READINGS)


def test_chosen_inspections_are_refused_naming_the_entry(
    api: TestClient, study_fleet: dict[str, int]
) -> None:
    ids = list(study_fleet.values())
    other_model = register_and_weigh(
        api, "XYZ 9", STUDY_TYPE_READINGS["AGL 7180"], make="Piaggio", model="Ape"
    )
    cases = [
        ([ids[0], 2**31 - 2], 404, ("inspection_ids[1]", "exists")),
        ([ids[0], other_model], 422, ("inspection_ids[1]", "same_model")),
        ([ids[0], ids[1], ids[0]], 422, ("inspection_ids[2]", "one_per_vehicle")),
        ([ids[0], 0], 422, ("inspection_ids[1]", "greater_than_equal")),
        ([ids[0], 2**31], 422, ("inspection_ids[1]", "less_than_equal")),
    ]
    for inspection_ids, status, expected in cases:
        response = api.post(
            "/api/v1/type-assessments", json={**STUDY_MODEL, "inspection_ids": inspection_ids}
        )
        assert response.status_code == status, response.text
        assert problem(response) == expected


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"model": "RE"}, "make"),
        ({"make": "Bajaj", "model": ""}, "model"),
        ({"make": "Bajaj", "model": "RE", "model_year": 1800}, "model_year"),
        ({"make": "Bajaj", "model": "RE", "colour": "green"}, "colour"),
    ],
)
def test_bad_bodies_are_422_naming_the_field(api: TestClient, body: dict[str, Any], field: str) -> None:
    response = api.post("/api/v1/type-assessments", json=body)
    assert response.status_code == 422
    assert problem(response)[0] == field


def test_a_station_sees_only_its_own_inspections_and_type_assessments(
    api: TestClient, client: TestClient, session: Session, study_fleet: dict[str, int]
) -> None:
    created = api.post("/api/v1/type-assessments", json=STUDY_MODEL).json()
    _station, other_key = create_station(session, name="Other weighbridge")
    other = {"Authorization": f"Bearer {other_key}"}
    assert client.get(f"/api/v1/type-assessments/{created['id']}", headers=other).status_code == 404
    ids = list(study_fleet.values())
    chosen = client.post(
        "/api/v1/type-assessments", json={**STUDY_MODEL, "inspection_ids": ids}, headers=other
    )
    assert chosen.status_code == 404
    assert problem(chosen) == ("inspection_ids[0]", "exists")
    latest = client.post("/api/v1/type-assessments", json=STUDY_MODEL, headers=other)
    assert latest.status_code == 422
    assert problem(latest) == ("model", "too_few")
    unknown = {"Authorization": "Bearer not-a-station-key"}
    assert client.post("/api/v1/type-assessments", json=STUDY_MODEL, headers=unknown).status_code == 401
