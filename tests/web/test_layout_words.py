"""The officer's pages word a tadpole's and a quadricycle's tyres and front axle as the vehicle has them:
the figures form, the inspection form's lift weighing and hints, the vehicle page, the registration
form and the type assessment's limit (reference section 9); the delta's words stay as they were."""

from __future__ import annotations

import html
from decimal import Decimal
from typing import Any

from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.accounts.service import create_user
from app.dynamics.models import VehicleDynamicsRevision
from web.test_web_dynamics import text_of
from web.webtools import OFFICER_EMAIL, PASSWORD, post_form, sign_in

VEHICLES = "/api/v1/vehicles"
TADPOLE: dict[str, Any] = {
    "registration_number": "TDP 101 EV",
    "layout": "tadpole",
    "make": "Example",
    "model": "E-Tadpole",
    "wheelbase_m": 1.9,
    "front_track_m": 1.2,
    "seats": [{"role": "driver", "x_m": 0.7}, *[{"role": "passenger", "x_m": 1.35}] * 3],
}
TADPOLE_FORM_READINGS = {"left_front_kg_1": "186", "right_front_kg_1": "182", "rear_kg_1": "112"}
QUADRICYCLE: dict[str, Any] = {
    "registration_number": "QDC 202 AA",
    "layout": "quadricycle",
    "make": "Bajaj",
    "model": "Qute",
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 1.0}, {"role": "passenger", "x_m": 1.8}],
}
FIGURES = "/vehicles/TDP101EV/dynamics"
NEW_INSPECTION = "/vehicles/TDP101EV/inspections/new"


def as_officer(api: TestClient, session: Session, *vehicles: dict[str, Any]) -> TestClient:
    """Register the vehicles through the API, then sign the same client in as an officer."""
    for vehicle in vehicles:
        registered = api.post(VEHICLES, json=vehicle)
        assert registered.status_code == 201, registered.text
    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    return api


def shown(page: str) -> str:
    return html.unescape(page)


def test_a_tadpole_s_figures_name_its_tyres_and_ask_for_no_rear_track(
    api: TestClient, session: Session
) -> None:
    web = as_officer(api, session, TADPOLE | {"track_m": 1.1}, QUADRICYCLE)
    form = shown(web.get(FIGURES).text)
    assert 'name="track_m"' not in form  # one rear wheel: no rear track
    assert "Each front tyre's cornering stiffness (N/rad)" in form
    assert "Rear tyre cornering stiffness (N/rad)" in form
    assert "Each rear tyre" not in form
    refused = post_form(web, FIGURES, FIGURES, {"rear_cornering_stiffness_n_per_rad": "stiff"})
    assert refused.status_code == 422
    assert "Enter the rear tyre cornering stiffness (N/rad) as a number, or leave it blank" in shown(
        text_of(refused.text, "rear_cornering_stiffness_n_per_rad-error")
    )
    done = post_form(web, FIGURES, FIGURES, {"rear_cornering_stiffness_n_per_rad": "8000"})
    assert done.status_code == 303
    # The rear track the API recorded is not the page's to clear.
    session.expire_all()
    latest = session.scalars(
        select(VehicleDynamicsRevision).order_by(VehicleDynamicsRevision.id.desc())
    ).first()
    assert latest is not None
    assert (latest.track_m, latest.rear_cornering_stiffness_n_per_rad) == (Decimal("1.1"), Decimal(8000))
    summary = shown(web.get("/vehicles/TDP101EV").text)
    assert "Rear tyre cornering stiffness (N/rad)" in summary
    assert "Rear track" not in summary
    assert "Behind the front wheels’ centres (m)" in summary
    quadricycle = shown(web.get("/vehicles/QDC202AA/dynamics").text)
    assert 'name="track_m"' in quadricycle
    assert "Each front tyre's cornering stiffness (N/rad)" in quadricycle
    assert "Each rear tyre's cornering stiffness (N/rad)" in quadricycle


def test_a_tadpole_s_inspection_form_raises_and_weighs_its_front_axle(
    api: TestClient, session: Session
) -> None:
    web = as_officer(api, session, TADPOLE)
    form = shown(web.get(NEW_INSPECTION).text)
    assert "Centre of gravity height by raising the front axle (optional)" in form
    assert "Front axle raised by (m)" in form
    assert "Both front wheels’ reaction together, with the axle raised" in form
    assert "Distance from the line between the front wheels’ centres to the centre of the rear axle" in form
    assert "centre of the front wheel" not in form
    answer = post_form(
        web, NEW_INSPECTION, NEW_INSPECTION, {**TADPOLE_FORM_READINGS, "cg_lift_height_m": "0.40"}
    )
    assert answer.status_code == 422
    assert "Enter both front wheels’ reaction together with the axle raised, in kilograms" in shown(
        text_of(answer.text, "cg_front_kg_1-error")
    )
    answer = post_form(web, NEW_INSPECTION, NEW_INSPECTION, {**TADPOLE_FORM_READINGS, "cg_front_kg_1": "300"})
    assert "Enter how far the front axle was raised" in shown(text_of(answer.text, "cg_lift_height_m-error"))


def test_the_registration_form_says_where_two_front_wheels_are_measured_from(
    web: TestClient,
) -> None:
    form = shown(web.get("/vehicles/new").text)
    assert (
        "front wheel (two front wheels: the line between their centres) to the centre of the rear axle"
        in form
    )
    assert "front wheel (two front wheels: the line between their centres) to the seated person’s" in form


def test_a_tadpole_type_is_judged_against_one_third(api: TestClient, session: Session) -> None:
    for plate, rear in (("TDP 101 EV", "112"), ("TDP 102 EV", "114")):
        vehicle = TADPOLE | {"registration_number": plate}
        assert api.post(VEHICLES, json=vehicle).status_code == 201
        readings = {"left_front_kg": 186, "right_front_kg": 182, "rear_kg": float(rear)}
        weighed = api.post("/api/v1/inspections", json={"registration_number": plate, "readings": readings})
        assert weighed.status_code == 201, weighed.text
    assessed = api.post("/api/v1/type-assessments", json={"make": "Example", "model": "E-Tadpole"})
    assert assessed.status_code == 201, assessed.text
    web = as_officer(api, session)
    page = shown(web.get(f"/type-assessments/{assessed.json()['id']}").text)
    assert "a case complies only when the upper bound of the vehicles’ LSF is below 1/3." in page
    assert "only when the dotted line is below the dashed line at 1/3." in page
    assert "2/3" not in page
    new = shown(web.get("/type-assessments/new").text)
    assert (
        "below the limit of their layout (2/3 for a delta, 1/3 for a tadpole, 1/2 for a quadricycle)" in new
    )


def test_the_api_says_each_layout_s_limit_at_speed(client: TestClient) -> None:
    schemas = client.get("/openapi.json").json()["components"]["schemas"]
    described = schemas["CaseAtSpeedOut"]["properties"]["compliant_at_speed"]["description"]
    assert "below the layout's limit (2/3 delta, 1/3 tadpole, 1/2 quadricycle)" in described
