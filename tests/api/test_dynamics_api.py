"""The estimates beyond the static test through the station API: the study vehicle with the reference's
illustrative track, radius, seat heights, tyres and drag, and the lift weighing (sections 4 and 5)."""

from __future__ import annotations

from datetime import UTC, datetime
from decimal import Decimal
from typing import Any

import pytest
from fastapi.testclient import TestClient
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.config import get_settings
from app.dynamics.estimates import record_input
from app.dynamics.service import revision_figures
from app.inspections.record import CaseRow, InspectionRecord
from app.stability.dynamics import assess_dynamics

ILLUSTRATIVE: dict[str, Any] = {
    **STUDY_VEHICLE,
    "seats": [
        {"role": "driver", "x_m": 0.9303, "z_m": 0.75},
        *({"role": "passenger", "x_m": 1.6303, "z_m": 0.8} for _ in range(3)),
    ],
    "track_m": 1.15,
    "wheel_radius_m": 0.19,
    "front_cornering_stiffness_n_per_rad": 8000,
    "rear_cornering_stiffness_n_per_rad": 8000,
    "drag_area_m2": 1.6,
    "centre_of_pressure_height_m": 0.9,
}
LIFT = {"lift_height_m": 0.4, "front_kg": [94.8, 94.7, 94.9]}
WEIGHING = {"registration_number": "BDG 252 QH", "readings": STUDY_READINGS, "cg_lift": LIFT}


def figures(body: dict[str, Any]) -> list[tuple[Any, ...]]:
    return [
        tuple(
            case["dynamics"][name]
            for name in ("cg_height_m", "rollover_threshold_g", "tilt_angle_deg", "critical_speed_kmh")
        )
        for case in body["loading_cases"]
    ]


def test_the_answer_carries_each_cases_rollover_threshold_and_critical_speed(api: TestClient) -> None:
    registered = api.post("/api/v1/vehicles", json=ILLUSTRATIVE)
    assert registered.status_code == 201, registered.text
    assert registered.json()["dynamics"]["revision"] == 1
    assert registered.json()["dynamics"]["seat_heights_m"] == [0.75, 0.8, 0.8, 0.8]
    answer = api.post("/api/v1/inspections", json=WEIGHING)
    assert answer.status_code == 201, answer.text
    body = answer.json()
    assert figures(body) == [
        (0.5503, 0.7277, 36.04, 113.8),
        (0.5836, 0.648, 32.94, None),
        (0.6146, 0.6365, 32.47, 142.1),
        (0.6378, 0.6285, 32.15, 88.8),
        (0.6559, 0.6227, 31.91, 70.0),
    ]
    assert body["loading_cases"][1]["dynamics"]["understeer_margin_nm_per_rad"] == 427.9
    assert body["dynamics_missing"] == []
    # the verdict is the static one, untouched
    assert [c["compliant"] for c in body["loading_cases"]] == [False, True, False, False, False]
    assert api.get(f"/api/v1/inspections/{body['id']}").json() == body


def test_at_60_kmh_the_driver_case_turns_non_compliant_and_its_margin_lasts_to_33_6_kmh(
    api: TestClient,
) -> None:
    api.post("/api/v1/vehicles", json=ILLUSTRATIVE)
    inspection = api.post("/api/v1/inspections", json=WEIGHING).json()
    answer = api.get(f"/api/v1/inspections/{inspection['id']}/dynamics", params={"speed_kmh": 60})
    assert answer.status_code == 200, answer.text
    body = answer.json()
    driver = body["loading_cases"][1]
    assert (driver["lsf"], driver["compliant"]) == (0.6578, True)
    assert (driver["lsf_at_speed"], driver["compliant_at_speed"], driver["margin_speed_kmh"]) == (
        0.6861,
        False,
        33.6,
    )
    assert [c["margin_speed_kmh"] is None for c in body["loading_cases"]] == [True, False, True, True, True]
    assert body["inputs"]["empty_cg_height_m"] == 0.5503
    assert body["inputs"]["cg_lift_front_kg"] == 94.8
    assert (body["inputs"]["air_density_kg_m3"], body["inputs"]["g_ms2"]) == (1.2, 9.80665)
    assert body["missing"] == []
    # accelerating moves more load rearward
    faster = api.get(
        f"/api/v1/inspections/{inspection['id']}/dynamics", params={"speed_kmh": 60, "acceleration_ms2": 1.5}
    ).json()
    assert faster["loading_cases"][1]["lsf_at_speed"] > driver["lsf_at_speed"]


def test_the_air_density_is_a_setting(api: TestClient, monkeypatch: pytest.MonkeyPatch) -> None:
    api.post("/api/v1/vehicles", json=ILLUSTRATIVE)
    inspection = api.post("/api/v1/inspections", json=WEIGHING).json()
    monkeypatch.setenv("TRIKECERT_AIR_DENSITY_KG_M3", "1.0")
    get_settings.cache_clear()
    body = api.get(f"/api/v1/inspections/{inspection['id']}/dynamics", params={"speed_kmh": 60}).json()
    get_settings.cache_clear()
    assert body["inputs"]["air_density_kg_m3"] == 1.0
    assert body["loading_cases"][1]["margin_speed_kmh"] == round(33.6225 * (1.2 / 1.0) ** 0.5, 1)


def test_a_vehicle_without_the_figures_gets_nulls_and_the_names_of_what_is_missing(api: TestClient) -> None:
    api.post("/api/v1/vehicles", json=STUDY_VEHICLE)
    body = api.post(
        "/api/v1/inspections", json={"registration_number": "BDG 252 QH", "readings": STUDY_READINGS}
    ).json()
    assert all(set(c["dynamics"].values()) == {None} for c in body["loading_cases"])
    assert body["dynamics_missing"] == [
        "cg_lift or cg_height_m",
        "track_m",
        "front_cornering_stiffness_n_per_rad",
        "rear_cornering_stiffness_n_per_rad",
    ]
    at_speed = api.get(f"/api/v1/inspections/{body['id']}/dynamics", params={"speed_kmh": 50}).json()
    assert "drag_area_m2" in at_speed["missing"]
    assert all(c["lsf_at_speed"] is None for c in at_speed["loading_cases"])


def test_a_given_cg_height_is_used_and_an_own_seat_layout_has_no_heights(api: TestClient) -> None:
    api.post("/api/v1/vehicles", json=ILLUSTRATIVE)
    given = api.post(
        "/api/v1/inspections",
        json={"registration_number": "BDG 252 QH", "readings": STUDY_READINGS, "cg_height_m": 0.55},
    ).json()
    assert given["loading_cases"][0]["dynamics"]["cg_height_m"] == 0.55
    own = api.post(
        "/api/v1/inspections",
        json={**WEIGHING, "occupants": {"seats": [{"role": "driver", "x_m": 0.93}]}},
    ).json()
    assert own["loading_cases"][0]["dynamics"]["rollover_threshold_g"] == 0.7277
    assert own["loading_cases"][1]["dynamics"]["rollover_threshold_g"] is None
    assert own["dynamics_missing"] == ["seats[0].z_m"]


REFUSED: list[tuple[dict[str, Any], str, str]] = [
    ({"cg_lift": {"lift_height_m": 0.4, "front_kg": 108}}, "cg_lift.front_kg", "less_than_level"),
    ({"cg_lift": {"lift_height_m": 2.0, "front_kg": 94.8}}, "cg_lift.lift_height_m", "below_wheelbase"),
    ({"cg_height_m": 0.19}, "cg_height_m", "above_wheel_centre"),
    ({"cg_height_m": 0.6, "cg_lift": LIFT}, "cg_height_m", "one_of"),
]


@pytest.mark.parametrize(("extra", "field", "rule"), REFUSED)
def test_a_bad_cg_weighing_is_refused_naming_the_field_and_nothing_is_stored(
    api: TestClient, extra: dict[str, Any], field: str, rule: str
) -> None:
    api.post("/api/v1/vehicles", json=ILLUSTRATIVE)
    refused = api.post(
        "/api/v1/inspections", json={"registration_number": "BDG 252 QH", "readings": STUDY_READINGS, **extra}
    )
    assert refused.status_code == 422, refused.text
    problems = refused.json()["errors"]
    assert any(p["field"] == field and p["rule"] == rule for p in problems), refused.text
    assert api.get("/api/v1/inspections").json()["total"] == 0


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"track_m": 0}, "track_m"),
        ({"track_m": -1.15}, "track_m"),
        ({"front_cornering_stiffness_n_per_rad": 0}, "front_cornering_stiffness_n_per_rad"),
        ({"seats": [{"role": "driver", "x_m": 0.93, "z_m": 0.1}]}, "seats[0].z_m"),
        ({"seats": [{"role": "driver", "x_m": 0.93, "z_m": 2.5}]}, "seats[0].z_m"),
    ],
)
def test_a_vehicle_with_an_impossible_figure_is_refused(
    api: TestClient, change: dict[str, Any], field: str
) -> None:
    refused = api.post("/api/v1/vehicles", json={**ILLUSTRATIVE, **change})
    assert refused.status_code == 422, refused.text
    assert field in refused.text


@pytest.mark.parametrize(
    "params",
    [
        {"speed_kmh": -1},
        {"speed_kmh": 250},
        {"speed_kmh": "nan"},
        {"acceleration_ms2": 11},
        {"speed_kmh": "fast"},
    ],
)
def test_bad_speed_parameters_are_422(api: TestClient, params: dict[str, Any]) -> None:
    api.post("/api/v1/vehicles", json=ILLUSTRATIVE)
    inspection = api.post("/api/v1/inspections", json=WEIGHING).json()
    assert api.get(f"/api/v1/inspections/{inspection['id']}/dynamics", params=params).status_code == 422


def test_an_inspection_stored_before_the_migration_reads_with_every_estimate_unknown() -> None:
    # The columns the migration added are NULL on every older row: no revision, no lift weighing.
    lsf, variance = Decimal("0.69637883"), Decimal("-0.02971216")
    case = CaseRow(0, Decimal(359), Decimal(250), lsf, variance, False, False, "")
    old = InspectionRecord(
        id=1,
        registration_number="BDG 252 QH",
        station_name=None,
        vehicle_id=1,
        station_id=None,
        user_id=None,
        created_at=datetime(2026, 11, 1, tzinfo=UTC),
        wheelbase_m=Decimal(2),
        occupant_mass_kg=Decimal(72),
        sum_tolerance=Decimal("0.01"),
        rules_version="lsf<2/3:cumulative-cases:v1",
        occupant_config={"seats": [], "load_items": []},
        front_kg=Decimal(108),
        left_rear_kg=Decimal(115),
        right_rear_kg=Decimal(135),
        overall_kg=Decimal(359),
        cg_from_front_m=Decimal("1.39276"),
        compliant=False,
        max_compliant_occupants=0,
        calibration_certificate=None,
        calibration_valid_until=None,
        dynamics_revision_id=None,
        dynamics_input=None,
        readings=(),
        cases=(case,),
    )
    dynamics = assess_dynamics(record_input(old, revision_figures(None)))
    assert dynamics.cases[0].rollover_threshold_g is None
    assert "track_m" in dynamics.missing
