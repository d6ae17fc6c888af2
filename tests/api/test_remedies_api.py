"""GET /api/v1/inspections/{id}/remedies: the study vehicle's remedies as the issue gives them, the
parameters, their refusals, a compliant vehicle, measured cases and station scoping."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.stations.service import create_station


def weigh(api: TestClient, vehicle: dict[str, Any], readings: dict[str, Any], **extra: Any) -> int:
    """Register the vehicle and submit one weighing; the inspection's id."""
    assert api.post("/api/v1/vehicles", json=vehicle).status_code == 201
    body = {"registration_number": vehicle["registration_number"], "readings": readings, **extra}
    created = api.post("/api/v1/inspections", json=body)
    assert created.status_code == 201, created.text
    inspection_id: int = created.json()["id"]
    return inspection_id


@pytest.fixture
def study_id(api: TestClient) -> int:
    return weigh(api, STUDY_VEHICLE, STUDY_READINGS)


def test_the_study_vehicle_gets_the_issues_figures(api: TestClient, study_id: int) -> None:
    response = api.get(f"/api/v1/inspections/{study_id}/remedies")
    assert response.status_code == 200, response.text
    body = response.json()
    assert body["target_occupants"] == 4
    assert body["compliant"] is False
    assert body["max_compliant_occupants"] == 1
    assert body["ballast"] == {
        "x_m": 0.3,
        "min_mass_kg": 54.64,
        "binding_occupants": 4,
        "possible": True,
        "unfixable_occupants": [],
    }
    assert body["seat_shift"] == {
        "min_forward_m": 0.262,
        "binding_occupants": 4,
        "possible": False,
        "unfixable_occupants": [0],
    }
    assert body["rear_tyre_ratio"] == {"min_ratio": 1.226, "binding_occupants": 4}
    rows = [
        (c["occupants"], c["lsf"], c["ballast_kg"], c["seat_shift_m"], c["tyre_ratio"]) for c in body["cases"]
    ]
    # The reference's section 6 table, each figure rounded up to its advised step.
    assert rows == [
        (0, 0.6964, 20.65, None, 1.147),
        (1, 0.6578, None, None, 0.961),
        (2, 0.6803, 13.26, 0.191, 1.064),
        (3, 0.6972, 33.95, 0.244, 1.152),
        (4, 0.7103, 54.64, 0.262, 1.226),
    ]
    assert [c["compliant_after_ballast"] for c in body["cases"]] == [True] * 5
    assert [c["compliant_after_seat_shift"] for c in body["cases"]] == [False, True, True, True, True]
    assert body["cases"][0]["lsf_after_seat_shift"] == 0.696379  # the empty vehicle is unchanged
    assert body["cases"][4]["lsf_after_ballast"] == 0.666666  # just below 2/3 (0.6666655...)


def test_ballast_ahead_of_the_front_wheel_and_a_lower_target(api: TestClient, study_id: int) -> None:
    ahead = api.get(f"/api/v1/inspections/{study_id}/remedies", params={"ballast_x_m": "-0.20"}).json()
    assert ahead["ballast"]["x_m"] == -0.2
    assert ahead["ballast"]["min_mass_kg"] == 36.83  # 36.8216 kg exactly: rounded up to suffice
    two = api.get(f"/api/v1/inspections/{study_id}/remedies", params={"target_occupants": 2}).json()
    assert two["target_occupants"] == 2
    assert [c["occupants"] for c in two["cases"]] == [0, 1, 2]
    assert two["ballast"]["min_mass_kg"] == 20.65
    assert two["ballast"]["binding_occupants"] == 0


def test_ballast_behind_two_thirds_of_the_wheelbase_is_not_possible(api: TestClient, study_id: int) -> None:
    body = api.get(f"/api/v1/inspections/{study_id}/remedies", params={"ballast_x_m": "1.5"}).json()
    assert body["ballast"] == {
        "x_m": 1.5,
        "min_mass_kg": None,
        "binding_occupants": None,
        "possible": False,
        "unfixable_occupants": [0, 2, 3, 4],
    }
    assert all(c["ballast_kg"] is None and c["lsf_after_ballast"] is None for c in body["cases"])


@pytest.mark.parametrize(
    ("params", "field", "rule"),
    [
        ({"target_occupants": 5}, "target_occupants", "range"),
        ({"target_occupants": 13}, "target_occupants", "less_than_equal"),
        ({"target_occupants": -1}, "target_occupants", "greater_than_equal"),
        ({"target_occupants": "four"}, "target_occupants", "int_parsing"),
        ({"ballast_x_m": "abc"}, "ballast_x_m", "decimal_parsing"),
        ({"ballast_x_m": "nan"}, "ballast_x_m", "finite_number"),
        ({"ballast_x_m": "9"}, "ballast_x_m", "less_than_equal"),
        ({"ballast_x_m": "3.5"}, "ballast_x_m", "range"),  # beyond this vehicle's reach (WB 2 m + 1 m)
        ({"ballast_x_m": "0.12345"}, "ballast_x_m", "precision"),
    ],
)
def test_bad_parameters_are_422_naming_the_field(
    api: TestClient, study_id: int, params: dict[str, Any], field: str, rule: str
) -> None:
    response = api.get(f"/api/v1/inspections/{study_id}/remedies", params=params)
    assert response.status_code == 422, response.text
    problem = response.json()["errors"][0]
    assert problem["field"] == field
    assert problem["rule"] == rule
    assert field in problem["message"] or field in response.json()["detail"]


def test_a_target_above_the_seats_says_how_many_there_are(api: TestClient, study_id: int) -> None:
    response = api.get(f"/api/v1/inspections/{study_id}/remedies", params={"target_occupants": 5})
    assert response.json()["detail"] == (
        "target_occupants: the vehicle has 4 seat(s); choose from 0 to 4 occupants, got 5"
    )


def test_a_compliant_vehicle_needs_nothing(api: TestClient) -> None:
    vehicle = {**STUDY_VEHICLE, "registration_number": "KJA 100 AA"}
    inspection_id = weigh(api, vehicle, {"front_kg": 200, "left_rear_kg": 95, "right_rear_kg": 95})
    body = api.get(f"/api/v1/inspections/{inspection_id}/remedies").json()
    assert body["compliant"] is True
    assert body["ballast"] is None
    assert body["seat_shift"] is None
    assert body["rear_tyre_ratio"] is None
    assert all(c["compliant"] and c["ballast_kg"] is None for c in body["cases"])


def test_measured_cases_and_load_items_are_rebuilt_exactly(api: TestClient) -> None:
    """Repeated readings averaged over three (non-terminating) and a weighed case: same LSFs as stored."""
    vehicle = {**STUDY_VEHICLE, "registration_number": "KJA 200 BB"}
    readings = {
        "front_kg": [108, 108.1, 108.1],
        "left_rear_kg": 115,
        "right_rear_kg": 135,
        "overall_kg": 359.2,
    }
    measured = [{"occupants": 2, "readings": {"front_kg": 162, "left_rear_kg": 170, "right_rear_kg": 171}}]
    load = [{"label": "tool box", "mass_kg": 12.5, "x_m": 2.1}]
    inspection_id = weigh(api, vehicle, readings, measured_cases=measured, load_items=load)
    stored = api.get(f"/api/v1/inspections/{inspection_id}").json()["loading_cases"]
    body = api.get(f"/api/v1/inspections/{inspection_id}/remedies").json()
    assert [c["lsf"] for c in body["cases"]] == [c["lsf"] for c in stored]
    assert body["cases"][2]["compliant"] is False
    assert body["cases"][2]["seat_shift_m"] is not None


def test_another_station_gets_404_and_no_key_401(
    api: TestClient, client: TestClient, session: Session, study_id: int
) -> None:
    _other, key = create_station(session, name="Other weighbridge")
    path = f"/api/v1/inspections/{study_id}/remedies"
    other = client.get(path, headers={"Authorization": f"Bearer {key}"})
    assert other.status_code == 404
    assert other.json()["errors"][0]["field"] == "inspection_id"
    assert client.get(path, headers={"Authorization": ""}).status_code == 401
    assert api.get(f"/api/v1/inspections/{study_id + 1000}/remedies").status_code == 404


def test_openapi_has_the_example_body(client: TestClient) -> None:
    schema = client.get("/openapi.json").json()
    example = schema["components"]["schemas"]["RemediesOut"]["examples"][0]
    assert example["ballast"]["min_mass_kg"] == 54.64
    assert "/api/v1/inspections/{inspection_id}/remedies" in schema["paths"]
