"""Tadpoles and quadricycles through the station API, the officer's page and the PDF (reference section 9).

The worked tadpole reproduces to the digit at each door; a reading of another layout, a missing wheel
and an unknown layout are refused by name with nothing stored; the exact limits hold at the API.
"""

from __future__ import annotations

import io
from typing import Any

import pytest
from fastapi.testclient import TestClient
from pypdf import PdfReader
from sqlalchemy import Engine, func, select, update
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session
from web.webtools import OFFICER_EMAIL, PASSWORD, post_form, sign_in

from app.accounts.service import create_user
from app.inspections.models import Inspection
from app.vehicles.models import Vehicle

VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"
TADPOLE: dict[str, Any] = {
    "registration_number": "TDP 101 EV",
    "layout": "tadpole",
    "make": "Example",
    "model": "E-Tadpole",
    "wheelbase_m": 1.9,
    "seats": [{"role": "driver", "x_m": 0.7}, *[{"role": "passenger", "x_m": 1.35}] * 3],
}
TADPOLE_READINGS = {"left_front_kg": 186, "right_front_kg": 182, "rear_kg": 112, "overall_kg": 480}
QUADRICYCLE: dict[str, Any] = {
    "registration_number": "QDC 202 AA",
    "layout": "quadricycle",
    "make": "Bajaj",
    "model": "Qute",
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 1.0}, {"role": "passenger", "x_m": 1.8}],
}
# Section 9's table: total, rear, LSF and variance 1/3 - LSF to the reference's digits, and the verdict.
TADPOLE_TABLE = [
    (480.0, 112.00, 0.2333, 0.1000, True),
    (552.0, 138.53, 0.2510, 0.0824, True),
    (624.0, 189.68, 0.3040, 0.0294, True),
    (696.0, 240.84, 0.3460, -0.0127, False),
    (768.0, 292.00, 0.3802, -0.0469, False),
]


def registered(api: TestClient, vehicle: dict[str, Any]) -> dict[str, Any]:
    response = api.post(VEHICLES, json=vehicle)
    assert response.status_code == 201, response.text
    body: dict[str, Any] = response.json()
    return body


def weighed(api: TestClient, registration: str, readings: dict[str, Any]) -> dict[str, Any]:
    response = api.post(INSPECTIONS, json={"registration_number": registration, "readings": readings})
    assert response.status_code == 201, response.text
    body: dict[str, Any] = response.json()
    return body


def test_the_worked_tadpole_reproduces_through_the_api(api: TestClient) -> None:
    vehicle = registered(api, TADPOLE)
    assert vehicle["layout"] == "tadpole"
    assert api.get(f"{VEHICLES}/tdp-101-ev").json()["layout"] == "tadpole"
    answer = weighed(api, "TDP 101 EV", TADPOLE_READINGS)
    assert answer["layout"] == "tadpole"
    assert answer["settings"]["lsf_limit"] == "1/3"
    assert answer["settings"]["rules_version"] == "lsf<1/3:cumulative-cases:v1"
    assert answer["readings"] == {
        "left_front_kg": 186.0,
        "right_front_kg": 182.0,
        "rear_kg": 112.0,
        "overall_kg": 480.0,
        "total_kg": 480.0,
    }
    table = [
        (c["total_kg"], c["rear_kg"], c["lsf"], c["variance"], c["compliant"])
        for c in answer["loading_cases"]
    ]
    assert table == TADPOLE_TABLE
    assert answer["compliant"] is False
    assert answer["max_compliant_occupants"] == 2  # the driver and one passenger
    assert api.get(f"{INSPECTIONS}/{answer['id']}").json() == answer


def test_a_quadricycle_exactly_at_one_half_is_not_compliant_through_the_api(api: TestClient) -> None:
    registered(api, QUADRICYCLE)
    readings = {"left_front_kg": 88.8, "right_front_kg": 96.3, "left_rear_kg": 90.0, "right_rear_kg": 95.1}
    assert (90.0 + 95.1) / (88.8 + 96.3 + 90.0 + 95.1) < 0.5  # floats would pass it
    answer = weighed(api, "QDC 202 AA", readings)
    empty = answer["loading_cases"][0]
    assert (empty["lsf"], empty["variance"], empty["compliant"]) == (0.5, 0.0, False)
    assert answer["settings"]["lsf_limit"] == "1/2"


def test_the_delta_is_the_default_and_its_answer_names_no_layout(api: TestClient, session: Session) -> None:
    study = {k: v for k, v in TADPOLE.items() if k != "layout"} | {"registration_number": "BDG 252 QH"}
    body = registered(api, study)
    assert "layout" not in body  # the delta's answers are as they always were
    assert session.scalar(select(Vehicle.layout)) == "delta"


def _counts(session: Session) -> tuple[int, int]:
    session.expire_all()
    return (
        session.scalar(select(func.count()).select_from(Vehicle)) or 0,
        session.scalar(select(func.count()).select_from(Inspection)) or 0,
    )


@pytest.mark.parametrize(
    ("url", "body", "field", "rule", "words"),
    [
        (
            VEHICLES,
            TADPOLE | {"registration_number": "SDC 1", "layout": "sidecar"},
            "layout",
            "literal_error",
            ("'delta', 'tadpole' or 'quadricycle'",),
        ),
        (
            INSPECTIONS,
            {"registration_number": "TDP 101 EV", "readings": TADPOLE_READINGS | {"front_kg": 108}},
            "readings.front_kg",
            "extra_forbidden",
            ("not a reading of a tadpole vehicle", "left_front_kg, right_front_kg, rear_kg"),
        ),
        (
            INSPECTIONS,
            {
                "registration_number": "QDC 202 AA",
                "readings": {"left_front_kg": 150, "right_front_kg": 148, "left_rear_kg": 140},
            },
            "readings.right_rear_kg",
            "missing",
            ("required", "quadricycle", "left_front_kg, right_front_kg, left_rear_kg, right_rear_kg"),
        ),
        (
            INSPECTIONS,
            {
                "registration_number": "TDP 101 EV",
                "readings": TADPOLE_READINGS,
                "measured_cases": [
                    {"occupants": 1, "readings": {"front_kg": 200, "left_rear_kg": 150, "right_rear_kg": 150}}
                ],
            },
            "measured_cases[0].readings.front_kg",
            "extra_forbidden",
            ("tadpole",),
        ),
    ],
    ids=[
        "an unknown layout",
        "a delta's wheel on a tadpole",
        "a quadricycle's wheel missing",
        "a measured case",
    ],
)
def test_bad_layouts_and_wheels_are_refused_by_name_and_nothing_is_stored(
    api: TestClient,
    session: Session,
    url: str,
    body: dict[str, Any],
    field: str,
    rule: str,
    words: tuple[str, ...],
) -> None:
    registered(api, TADPOLE)
    registered(api, QUADRICYCLE)
    before = _counts(session)
    response = api.post(url, json=body)
    assert response.status_code == 422, response.text
    [problem] = response.json()["errors"]
    assert (problem["field"], problem["rule"]) == (field, rule)
    for word in words:
        assert word in problem["message"]
    assert _counts(session) == before


def _pdf_text(api: TestClient, number: str) -> str:
    response = api.get(f"/api/v1/certificates/{number}/pdf")
    assert response.status_code == 200
    reader = PdfReader(io.BytesIO(response.content))
    return " ".join(" ".join(page.extract_text().split()) for page in reader.pages)


def test_the_tadpole_s_refusal_and_page_show_its_limit_and_its_rear_wheel(
    api: TestClient, session: Session
) -> None:
    registered(api, TADPOLE)
    inspection = weighed(api, "TDP 101 EV", TADPOLE_READINGS)
    issued = api.post(f"{INSPECTIONS}/{inspection['id']}/certificate")
    assert issued.status_code == 201, issued.text
    refusal = issued.json()
    assert refusal["kind"] == "refusal"
    text = _pdf_text(api, refusal["number"])
    assert "Weight on the rear wheel (kg)" in text
    assert "Weight on rear wheels" not in text
    assert "1/3 (0.333)" in text
    assert "2/3" not in text
    assert "limit 1/3" in text
    for name in ("Left front wheel: 186", "Right front wheel: 182", "Rear wheel: 112"):
        assert name in text
    assert "Driver + 2 passengers: LSF 0.346 is above the limit 1/3 (0.333) by 0.013" in text

    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    page = api.get(f"/inspections/{inspection['id']}").text
    assert "Weight on the rear wheel (kg)" in page
    assert "1/3 (0.333)" in page
    assert "limit 1/3" in page
    assert "Tadpole (two front wheels and one rear wheel)" in page
    for figure in ("0.233", "0.251", "0.304", "0.346", "0.380", "+0.100", "+0.082", "+0.029"):
        assert figure in page
    statistics = api.get("/statistics").text
    assert 'id="per-layout"' in statistics
    assert "Tadpole (two front wheels and one rear wheel): limit 1/3 (0.333)" in statistics


def test_the_registration_form_refuses_an_unknown_layout_and_stores_nothing(
    client: TestClient, session: Session
) -> None:
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    fields = {
        "registration_number": "SDC 1",
        "layout": "sidecar",
        "make": "Example",
        "model": "Side",
        "wheelbase_m": "1.9",
        "driver_x_m": "0.7",
    }
    before = _counts(session)
    refused = post_form(client, "/vehicles/new", "/vehicles/new", fields)
    assert refused.status_code == 422
    assert "Choose the axle layout: delta, tadpole, quadricycle" in refused.text
    assert _counts(session) == before
    registered_page = post_form(client, "/vehicles/new", "/vehicles/new", fields | {"layout": "quadricycle"})
    assert registered_page.status_code == 303
    assert session.scalar(select(Vehicle.layout).where(Vehicle.registration_key == "SDC1")) == "quadricycle"


def test_the_database_keeps_a_vehicle_s_layout_as_registered(api: TestClient, owner_engine: Engine) -> None:
    registered(api, TADPOLE)
    # Even the owner's role (the app's has no UPDATE on vehicles at all on PostgreSQL) meets the trigger.
    with pytest.raises(DBAPIError, match="layout"), owner_engine.begin() as connection:
        connection.execute(update(Vehicle).values(layout="delta"))
