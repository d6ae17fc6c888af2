"""What a weighbridge station can do through the API: averaged readings, registrations found however
they are written, the inspection list with its filters and pages, measured cases and occupant
overrides. (The study's Table 4 itself is in test_study_vehicle.py.)"""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, datetime
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.inspections.models import Reading

VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"
# A front-heavy trike of our own: every loading case complies (LSF 0.444, 0.448, 0.500).
FRONT_HEAVY: dict[str, Any] = {
    "registration_number": "KTU-417-XA",
    "make": "TVS",
    "model": "King",
    "wheelbase_m": 2.0,
    "seats": [
        {"role": "driver", "x_m": 0.9303},
        {"role": "passenger", "x_m": 1.6303},
    ],
}
FRONT_HEAVY_READINGS: dict[str, Any] = {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80}


def rows(body: dict[str, Any]) -> list[tuple[int, float, float, float, bool, bool]]:
    return [
        (c["occupants"], c["total_kg"], c["rear_kg"], c["lsf"], c["compliant"], c["measured"])
        for c in body["loading_cases"]
    ]


@pytest.fixture
def study(api: TestClient) -> TestClient:
    """The API with the study's vehicle on file."""
    assert api.post(VEHICLES, json=STUDY_VEHICLE).status_code == 201
    return api


def submit(api: TestClient, **body: Any) -> dict[str, Any]:
    response = api.post(INSPECTIONS, json=body)
    assert response.status_code == 201, response.text
    result: dict[str, Any] = response.json()
    return result


def test_repeated_readings_are_averaged_and_kept_as_read(study: TestClient) -> None:
    body = submit(
        study,
        registration_number="BDG 252 QH",
        readings={
            "front_kg": [107, 108, 109],
            "left_rear_kg": [115.5, 114.5],
            "right_rear_kg": 135,
            "overall_kg": [358.5, 359.5],
        },
    )
    assert body["readings"] == {
        "front_kg": 108.0,
        "left_rear_kg": 115.0,
        "right_rear_kg": 135.0,
        "overall_kg": 359.0,
        "rear_kg": 250.0,
        "total_kg": 359.0,
    }
    assert body["raw_readings"] == {
        "front_kg": [107.0, 108.0, 109.0],
        "left_rear_kg": [115.5, 114.5],
        "right_rear_kg": [135.0],
        "overall_kg": [358.5, 359.5],
    }
    assert rows(body)[0] == (0, 359.0, 250.0, 0.6964, False, False)
    assert body["max_compliant_occupants"] == 1


def test_an_averaged_verdict_is_exact_at_the_two_thirds_boundary(study: TestClient) -> None:
    """The reference's float trap reached through averages: a = 103.2, b = 91.3, c = 115.1 is exactly 2/3."""
    body = submit(
        study,
        registration_number="BDG 252 QH",
        readings={"front_kg": [103.1, 103.3], "left_rear_kg": [91.2, 91.4], "right_rear_kg": [115, 115.2]},
    )
    assert rows(body)[0] == (0, 309.6, 206.4, 0.6667, False, False)
    assert body["loading_cases"][0]["variance"] == 0.0


@pytest.mark.parametrize("written", ["bdg-252qh", "BDG252QH", "bdg 252 qh", "Bdg-252-Qh", "BDG  252--QH"])
def test_a_registration_is_found_however_it_is_written(study: TestClient, written: str) -> None:
    response = study.get(f"{VEHICLES}/{written}")
    assert response.status_code == 200, response.text
    assert response.json()["registration_number"] == "BDG 252 QH"
    submitted = submit(study, registration_number=written, readings=STUDY_READINGS)
    assert submitted["registration_number"] == "BDG 252 QH"


def test_a_registered_vehicle_reads_back_as_registered(api: TestClient) -> None:
    created = api.post(VEHICLES, json={**FRONT_HEAVY, "chassis_number": " md2aac4zz "})
    assert created.status_code == 201, created.text
    found = api.get(f"{VEHICLES}/ktu417xa")
    assert found.status_code == 200
    assert found.json() == created.json()
    assert found.json() | {"id": 0, "created_at": ""} == {
        "id": 0,
        "registration_number": "KTU 417 XA",
        "make": "TVS",
        "model": "King",
        "model_year": None,
        "chassis_number": "MD2AAC4ZZ",
        "wheelbase_m": 2.0,
        "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
        # no figures for the estimates were given: revision 1 holds none of them
        "dynamics": {
            "revision": 1,
            "track_m": None,
            "wheel_radius_m": None,
            "seat_heights_m": [],
            "front_cornering_stiffness_n_per_rad": None,
            "rear_cornering_stiffness_n_per_rad": None,
            "drag_area_m2": None,
            "centre_of_pressure_height_m": None,
        },
        "created_at": "",
    }


def test_a_measured_case_replaces_the_moment_arithmetic_for_its_row(
    study: TestClient, session: Session
) -> None:
    measured = {"front_kg": 147.5, "left_rear_kg": 133.5, "right_rear_kg": 150, "overall_kg": 431}
    body = submit(
        study,
        registration_number="BDG 252 QH",
        readings=STUDY_READINGS,
        measured_cases=[{"occupants": 1, "readings": measured}],
    )
    assert rows(body) == [
        (0, 359.0, 250.0, 0.6964, False, False),
        (1, 431.0, 283.5, 0.6578, True, True),
        (2, 503.0, 342.18, 0.6803, False, False),
        (3, 575.0, 400.87, 0.6972, False, False),
        (4, 647.0, 459.56, 0.7103, False, False),
    ]
    assert body["max_compliant_occupants"] == 1
    stored = session.scalar(
        select(func.count())
        .select_from(Reading)
        .where(Reading.inspection_id == body["id"], Reading.case_occupants == 1)
    )
    assert stored == 4  # the measured case's own raw readings are kept too


def test_occupants_override_the_mass_and_the_seats_of_the_vehicle(study: TestClient) -> None:
    body = submit(
        study,
        registration_number="BDG 252 QH",
        readings=STUDY_READINGS,
        occupants={
            "mass_kg": 80,
            "seats": [{"role": "driver", "x_m": 0.9}, {"role": "passenger", "x_m": 1.7}],
        },
    )
    # rear 250 + 80 * 0.9 / 2 = 286 of 439; then + 80 * 1.7 / 2 = 354 of 519.
    assert rows(body) == [
        (0, 359.0, 250.0, 0.6964, False, False),
        (1, 439.0, 286.0, 0.6515, True, False),
        (2, 519.0, 354.0, 0.6821, False, False),
    ]
    assert body["settings"]["occupant_mass_kg"] == 80.0
    assert body["seats"] == [{"role": "driver", "x_m": 0.9}, {"role": "passenger", "x_m": 1.7}]
    assert body["max_compliant_occupants"] == 1
    assert body["compliant"] is False


def test_the_mass_alone_can_be_overridden_keeping_the_vehicles_seats(study: TestClient) -> None:
    body = submit(study, registration_number="BDG 252 QH", readings=STUDY_READINGS, occupants={"mass_kg": 60})
    assert [c["total_kg"] for c in body["loading_cases"]] == [359.0, 419.0, 479.0, 539.0, 599.0]
    assert len(body["seats"]) == 4
    assert body["settings"]["occupant_mass_kg"] == 60.0


def test_a_wheelbase_given_with_the_readings_is_used_for_that_inspection(study: TestClient) -> None:
    body = submit(study, registration_number="BDG 252 QH", readings=STUDY_READINGS, wheelbase_m=2.5)
    assert body["wheelbase_m"] == 2.5
    assert body["cg_from_front_m"] == 1.741  # 2.5 * 250 / 359
    assert study.get(f"{VEHICLES}/BDG252QH").json()["wheelbase_m"] == 2.0


@pytest.fixture
def listed(study: TestClient, backdate: Callable[..., None]) -> dict[str, int]:
    """Four inspections at fixed times: the study's vehicle thrice (NC), the front-heavy one once (C)."""
    assert study.post(VEHICLES, json=FRONT_HEAVY).status_code == 201
    study_weighing = {"registration_number": "BDG 252 QH", "readings": STUDY_READINGS}
    front_heavy_weighing = {"registration_number": "KTU 417 XA", "readings": FRONT_HEAVY_READINGS}
    ids = {
        "study january": submit(study, **study_weighing)["id"],
        "study february": submit(study, **study_weighing)["id"],
        "front-heavy march": submit(study, **front_heavy_weighing)["id"],
        "study april": submit(study, **study_weighing)["id"],
    }
    for month, inspection_id in enumerate(ids.values(), start=1):
        at = datetime(2026, month, 1, 8, 0, tzinfo=UTC)
        backdate(inspection_id, at)
    return ids


def listing(api: TestClient, query: str) -> tuple[list[int], int, dict[str, Any]]:
    response = api.get(f"{INSPECTIONS}?{query}")
    assert response.status_code == 200, response.text
    page: dict[str, Any] = response.json()
    return [item["id"] for item in page["items"]], page["total"], page


def test_the_list_is_newest_first_and_paginated(study: TestClient, listed: dict[str, int]) -> None:
    newest_first = list(reversed(listed.values()))
    ids, total, page = listing(study, "")
    assert (ids, total, page["limit"], page["offset"]) == (newest_first, 4, 50, 0)
    assert listing(study, "limit=3")[:2] == (newest_first[:3], 4)
    ids, total, page = listing(study, "limit=3&offset=3")
    assert (ids, total, page["limit"], page["offset"]) == (newest_first[3:], 4, 3, 3)
    assert listing(study, "offset=10")[:2] == ([], 4)


def test_the_list_item_is_a_summary(study: TestClient, listed: dict[str, int]) -> None:
    _ids, _total, page = listing(study, "registration_number=ktu417xa")
    assert page["items"] == [
        {
            "id": listed["front-heavy march"],
            "registration_number": "KTU 417 XA",
            "station": "Test weighbridge",
            "created_at": "2026-03-01T08:00:00Z",
            "compliant": True,
            "max_compliant_occupants": 2,
        }
    ]


@pytest.mark.parametrize(
    ("query", "expected", "total"),
    [
        ("registration_number=bdg-252qh", ["study april", "study february", "study january"], 3),
        ("registration_number=BDG%20252%20QH&limit=1", ["study april"], 3),
        ("registration_number=XYZ999", [], 0),
        ("compliant=true", ["front-heavy march"], 1),
        ("compliant=false", ["study april", "study february", "study january"], 3),
        ("since=2026-02-01T08:00:00Z", ["study april", "front-heavy march", "study february"], 3),
        ("since=2026-02-01T08:00:00.000001Z", ["study april", "front-heavy march"], 2),
        ("since=2026-02-01T09:00:00%2B01:00", ["study april", "front-heavy march", "study february"], 3),
        ("until=2026-03-01T08:00:00Z", ["study february", "study january"], 2),
        ("since=2026-02-01T00:00:00Z&until=2026-04-01T00:00:00Z", ["front-heavy march", "study february"], 2),
        (
            "since=2026-02-01T00:00:00Z&compliant=false&registration_number=bdg252qh",
            ["study april", "study february"],
            2,
        ),
    ],
)
def test_the_list_filters_combine(
    study: TestClient, listed: dict[str, int], query: str, expected: list[str], total: int
) -> None:
    ids, found, _page = listing(study, query)
    assert ids == [listed[name] for name in expected]
    assert found == total
