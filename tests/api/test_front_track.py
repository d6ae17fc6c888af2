"""Two front wheels tip about their own track: a tadpole's and a quadricycle's rollover threshold from
the front track on record (reference section 9), computed here separately, and a delta refused one."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient
from layout_vehicles import QUADRICYCLE, QUADRICYCLE_READINGS, SEAT_Z, TADPOLE, TADPOLE_READINGS
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from web.webtools import OFFICER_EMAIL, PASSWORD, sign_in

from app.accounts.service import create_user
from app.dynamics.models import VehicleDynamicsRevision
from app.vehicles.models import Vehicle

VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"
OCCUPANT_KG = 72.0
CG_HEIGHT = 0.55  # the empty vehicle's, given with the weighing


def _expected_thresholds(
    *,
    empty_front: float,
    empty_rear: float,
    wheelbase: float,
    seats_x: list[float],
    front_track: float,
    rear_track: float,
) -> list[float]:
    """Each case's threshold y / h, with y on the line through the outer contact points at the CG's
    station and h from the seated heights, computed from the readings and the seats alone."""
    thresholds = []
    for filled in range(len(seats_x) + 1):
        total = empty_front + empty_rear + OCCUPANT_KG * filled
        rear = empty_rear + sum(OCCUPANT_KG * x / wheelbase for x in seats_x[:filled])
        behind_front = rear / total * wheelbase  # the CG's station behind the front axle
        y = front_track / 2 + (rear_track / 2 - front_track / 2) * behind_front / wheelbase
        height = ((empty_front + empty_rear) * CG_HEIGHT + OCCUPANT_KG * SEAT_Z * filled) / total
        thresholds.append(y / height)
    return thresholds


def _weighed(api: TestClient, vehicle: dict[str, Any], readings: dict[str, Any]) -> dict[str, Any]:
    registered = api.post(VEHICLES, json=vehicle)
    assert registered.status_code == 201, registered.text
    answer = api.post(
        INSPECTIONS,
        json={
            "registration_number": vehicle["registration_number"],
            "readings": readings,
            "cg_height_m": CG_HEIGHT,
        },
    )
    assert answer.status_code == 201, answer.text
    body: dict[str, Any] = answer.json()
    return body


def _thresholds(answer: dict[str, Any]) -> list[float | None]:
    return [case["dynamics"]["rollover_threshold_g"] for case in answer["loading_cases"]]


def test_a_tadpole_tips_about_its_front_track_and_needs_no_rear_track(api: TestClient) -> None:
    answer = _weighed(api, TADPOLE, TADPOLE_READINGS)
    expected = _expected_thresholds(
        empty_front=368,
        empty_rear=112,
        wheelbase=1.9,
        seats_x=[0.7, 1.35, 1.35, 1.35],
        front_track=1.2,
        rear_track=0,
    )
    assert _thresholds(answer) == pytest.approx(expected, abs=5e-5)
    # The reference's form for a tadpole: (T_f / 2h)(1 - LSF); it falls as the load moves rearward.
    empty = answer["loading_cases"][0]
    assert empty["dynamics"]["rollover_threshold_g"] == pytest.approx(
        1.2 / (2 * CG_HEIGHT) * (1 - 7 / 30), abs=5e-5
    )
    assert "front_track_m" not in answer["dynamics_missing"]
    assert "track_m" not in answer["dynamics_missing"]  # one rear wheel: no rear track to know
    vehicle = api.get(f"{VEHICLES}/tdp-101-ev").json()
    assert vehicle["dynamics"]["front_track_m"] == 1.2
    at_speed = api.get(f"{INSPECTIONS}/{answer['id']}/dynamics", params={"speed_kmh": 30}).json()
    assert at_speed["inputs"]["front_track_m"] == 1.2


def test_a_quadricycle_with_equal_tracks_tips_at_t_over_2h_whatever_its_lsf(api: TestClient) -> None:
    answer = _weighed(api, QUADRICYCLE, QUADRICYCLE_READINGS)
    expected = _expected_thresholds(
        empty_front=238, empty_rear=182, wheelbase=2.0, seats_x=[1.0, 1.8], front_track=1.3, rear_track=1.3
    )
    assert _thresholds(answer) == pytest.approx(expected, abs=5e-5)
    assert answer["loading_cases"][0]["dynamics"]["rollover_threshold_g"] == pytest.approx(
        1.3 / (2 * CG_HEIGHT), abs=5e-5
    )


def test_two_front_wheels_without_a_front_track_name_it_missing_and_give_no_threshold(
    api: TestClient,
) -> None:
    answer = _weighed(api, {**TADPOLE, "front_track_m": None}, TADPOLE_READINGS)
    assert "front_track_m" in answer["dynamics_missing"]
    assert set(_thresholds(answer)) == {None}
    assert "front_track_m" not in api.get(f"{VEHICLES}/tdp-101-ev").json()["dynamics"]  # not recorded


def test_a_delta_given_a_front_track_is_refused_by_name_and_nothing_is_stored(
    api: TestClient, session: Session
) -> None:
    delta = {name: value for name, value in QUADRICYCLE.items() if name != "layout"}  # the default layout
    before = (
        session.scalar(select(func.count(Vehicle.id))),
        session.scalar(select(func.count(VehicleDynamicsRevision.id))),
    )
    refused = api.post(VEHICLES, json=delta)
    assert refused.status_code == 422
    assert refused.json()["errors"] == [
        {
            "field": "front_track_m",
            "rule": "front_track",
            "message": "front_track_m: a vehicle with one front wheel has no front track; leave it out",
        }
    ]
    after = (
        session.scalar(select(func.count(Vehicle.id))),
        session.scalar(select(func.count(VehicleDynamicsRevision.id))),
    )
    assert after == before
    accepted = api.post(VEHICLES, json={k: v for k, v in delta.items() if k != "front_track_m"})
    assert accepted.status_code == 201
    assert "front_track_m" not in accepted.json()["dynamics"]


def test_the_figures_page_asks_for_a_front_track_only_where_there_are_two_front_wheels(
    api: TestClient, session: Session
) -> None:
    _weighed(api, TADPOLE, TADPOLE_READINGS)
    delta = {k: v for k, v in QUADRICYCLE.items() if k not in ("layout", "front_track_m")}
    assert api.post(VEHICLES, json=delta).status_code == 201
    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    tadpole_form = api.get("/vehicles/tdp-101-ev/dynamics").text
    assert 'name="front_track_m"' in tadpole_form
    assert "Front track (m)" in tadpole_form
    assert 'value="1.2"' in tadpole_form
    assert "Front track (m)" in api.get("/vehicles/tdp-101-ev").text
    delta_form = api.get("/vehicles/qdc-202-aa/dynamics").text
    assert 'name="front_track_m"' not in delta_form
    assert "Front track" not in api.get("/vehicles/qdc-202-aa").text
