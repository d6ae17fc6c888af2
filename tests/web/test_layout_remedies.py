"""The remedies of a tadpole and a quadricycle in their own words: ballast placed from the front axle,
the reference's tadpole figures (section 9), ballast beyond the layout's share of the wheelbase, and
which way the remedies move the rollover threshold."""

from __future__ import annotations

import html
from typing import Any

from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from web.test_layout_words import QUADRICYCLE, TADPOLE, as_officer
from web.test_web_remedies import sentence

INSPECTIONS = "/api/v1/inspections"


def weigh(api: TestClient, registration: str, readings: dict[str, Any]) -> int:
    answer = api.post(INSPECTIONS, json={"registration_number": registration, "readings": readings})
    assert answer.status_code == 201, answer.text
    inspection: int = answer.json()["id"]
    return inspection


def test_a_tadpole_s_remedies_are_the_reference_s_and_placed_from_its_front_axle(
    api: TestClient, session: Session
) -> None:
    api.post("/api/v1/vehicles", json=TADPOLE)
    inspection = weigh(api, "TDP 101 EV", {"left_front_kg": 186, "right_front_kg": 182, "rear_kg": 112})
    officer = as_officer(api, session)
    page = html.unescape(officer.get(f"/inspections/{inspection}", params={"ballast_x_m": "0.20"}).text)
    said = html.unescape(sentence(page))
    assert said.startswith("Carry no more than the driver and one passenger; or ")
    assert "fit more than 157.85 kg of ballast 0.20 m behind the front axle" in said  # the reference's
    assert "front wheel" not in said
    assert "makes the vehicle a little harder to tip over on a bend" in page
    assert "tip over on a bend a little more easily" not in page


def test_ballast_too_far_back_on_a_quadricycle_is_refused_at_half_the_wheelbase(
    api: TestClient, session: Session
) -> None:
    api.post("/api/v1/vehicles", json=QUADRICYCLE)
    readings = {"left_front_kg": 100, "right_front_kg": 100, "left_rear_kg": 130, "right_rear_kg": 130}
    inspection = weigh(api, "QDC 202 AA", readings)
    officer = as_officer(api, session)
    page = html.unescape(officer.get(f"/inspections/{inspection}", params={"ballast_x_m": "1.20"}).text)
    said = html.unescape(sentence(page))
    assert said.endswith(
        "Ballast 1.20 m behind the front axle cannot help: it must sit less than half the wheelbase behind "
        "the front axle."
    )
    assert "two thirds" not in said
    assert "only as far as its front and rear tracks differ" in page
