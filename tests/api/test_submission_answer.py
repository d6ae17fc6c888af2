"""A station's answer to a submission is built from the values as stored (app/inspections/answer.py):
a later GET of the inspection gives the same document, figure for figure, whatever the submission
held; with an Idempotency-Key the replay is that same document too."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient
from study_data import STUDY_READINGS, STUDY_VEHICLE

INSPECTIONS = "/api/v1/inspections"
VEHICLE_FIGURES = {
    **STUDY_VEHICLE,
    "track_m": 1.15,
    "wheel_radius_m": 0.2,
    "seats": [
        {"role": "driver", "x_m": 0.9303, "z_m": 0.75},
        {"role": "passenger", "x_m": 1.6303, "z_m": 0.8},
        {"role": "passenger", "x_m": 1.6303, "z_m": 0.8},
        {"role": "passenger", "x_m": 1.6303, "z_m": 0.8},
    ],
}
REGISTRATION = STUDY_VEHICLE["registration_number"]

SUBMISSIONS: dict[str, dict[str, Any]] = {
    "the study's readings": {"readings": STUDY_READINGS},
    "repeated readings with a spread": {
        "readings": {
            "front_kg": [107.9, 108, 108.1],
            "left_rear_kg": [115.5, 114.5],
            "right_rear_kg": 135,
            "overall_kg": [358.5, 359.5],
        }
    },
    "the CG height by axle lift": {
        "readings": STUDY_READINGS,
        "cg_lift": {"lift_height_m": 0.4, "front_kg": [94.8, 94.9]},
    },
    "a measured case, a load item and an occupant mass": {
        "readings": STUDY_READINGS,
        "measured_cases": [
            {"occupants": 1, "readings": {"front_kg": 146.5, "left_rear_kg": 141.4, "right_rear_kg": 143.1}}
        ],
        "load_items": [{"label": "gas cylinder", "mass_kg": 12.5, "x_m": 2.3}],
        "occupants": {"mass_kg": 68.25},
    },
    "a seat layout of its own": {
        "readings": STUDY_READINGS,
        "wheelbase_m": 1.95,
        "occupants": {"seats": [{"role": "driver", "x_m": 0.95}, {"role": "passenger", "x_m": 1.4}]},
    },
}


@pytest.mark.parametrize("extra", SUBMISSIONS.values(), ids=SUBMISSIONS.keys())
def test_the_answer_is_the_stored_inspection_as_a_get_reads_it(
    api: TestClient, extra: dict[str, Any]
) -> None:
    assert api.post("/api/v1/vehicles", json=VEHICLE_FIGURES).status_code == 201

    answered = api.post(INSPECTIONS, json={"registration_number": REGISTRATION, **extra})
    assert answered.status_code == 201, answered.text
    read = api.get(f"{INSPECTIONS}/{answered.json()['id']}")

    assert read.status_code == 200
    assert answered.json() == read.json()
    assert answered.json()["loading_cases"], "Table 4 is there"


def test_a_replay_is_the_same_document_as_the_first_answer_and_the_stored_inspection(api: TestClient) -> None:
    assert api.post("/api/v1/vehicles", json=VEHICLE_FIGURES).status_code == 201
    body = {"registration_number": REGISTRATION, **SUBMISSIONS["the CG height by axle lift"]}
    headers = {"Idempotency-Key": "weighing-7"}

    first = api.post(INSPECTIONS, json=body, headers=headers)
    again = api.post(INSPECTIONS, json=body, headers=headers)

    assert (first.status_code, again.status_code) == (201, 201)
    assert again.headers["Idempotent-Replayed"] == "true"
    assert again.content == first.content
    assert first.json() == api.get(f"{INSPECTIONS}/{first.json()['id']}").json()
