"""Register a vehicle with its seat layout, find it by registration, read its page."""

from __future__ import annotations

import re

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.vehicles.models import Vehicle
from web.webtools import post_form

FORM = {
    "registration_number": "kja-123 xy",
    "make": "Bajaj",
    "model": "RE 4S",
    "model_year": "2019",
    "wheelbase_m": "2.000",
    "driver_x_m": "0.93",
    "passenger_x_m_1": "1.63",
    "passenger_x_m_2": "",
    "passenger_x_m_3": "1.63",
}


def test_registering_a_vehicle_stores_its_seats_driver_first_and_shows_its_page(
    web: TestClient, session: Session
) -> None:
    response = post_form(web, "/vehicles/new", "/vehicles/new", FORM)
    assert response.status_code == 303
    assert response.headers["location"] == "/vehicles/KJA123XY"
    vehicle = session.scalars(select(Vehicle)).one()
    assert vehicle.registration_number == "KJA 123 XY"
    assert [(s.role, str(s.x_m)) for s in vehicle.seats] == [
        ("driver", "0.9300"),
        ("passenger", "1.6300"),
        ("passenger", "1.6300"),
    ]
    page = web.get("/vehicles/KJA123XY")
    assert "Vehicle KJA 123 XY registered." in page.text
    assert "This vehicle has not been inspected yet." in page.text


def test_an_invalid_vehicle_is_shown_again_with_messages_beside_the_fields_and_nothing_stored(
    web: TestClient, session: Session
) -> None:
    response = post_form(
        web,
        "/vehicles/new",
        "/vehicles/new",
        {**FORM, "make": "", "wheelbase_m": "two", "passenger_x_m_3": "9"},
    )
    assert response.status_code == 422
    html = response.text
    assert "There is a problem" in html
    assert '<a href="#make">Enter the make, like Bajaj</a>' in html
    assert '<a href="#wheelbase_m">Enter the wheelbase as a number of metres, like 2.000</a>' in html
    assert 'id="make-error"' in html
    assert 'aria-describedby="wheelbase_m-hint wheelbase_m-error"' in html
    assert 'value="kja-123 xy"' in html  # the values stay
    assert "<title>Error: Register a vehicle" in html
    assert session.scalar(select(func.count()).select_from(Vehicle)) == 0


@pytest.mark.parametrize("others", [{}, {"wheelbase_m": ""}], ids=["alone", "with another mistake"])
def test_a_registration_the_api_refuses_is_refused_beside_the_field_in_the_api_s_words(
    web: TestClient, session: Session, others: dict[str, str]
) -> None:
    response = post_form(
        web, "/vehicles/new", "/vehicles/new", {**FORM, "registration_number": "BDG-252-QH!!", **others}
    )
    assert response.status_code == 422
    beside = re.search(r'id="registration_number-error"[^>]*>(.*?)</p>', response.text, re.S)
    assert beside is not None, "no message beside the registration number"
    assert "Use 2 to 16 letters and digits, like BDG 252 QH (spaces and hyphens are ignored)" in beside[1]
    assert 'href="#registration_number"' in response.text  # and in the summary above the form
    assert session.scalar(select(func.count()).select_from(Vehicle)) == 0


def test_a_seat_out_of_reach_is_refused_by_the_core_beside_its_own_field(
    web: TestClient, session: Session
) -> None:
    response = post_form(web, "/vehicles/new", "/vehicles/new", {**FORM, "passenger_x_m_3": "9"})
    assert response.status_code == 422
    assert 'href="#passenger_x_m_3"' in response.text
    assert 'id="passenger_x_m_3-error"' in response.text
    assert session.scalar(select(func.count()).select_from(Vehicle)) == 0


def test_a_registration_already_on_file_is_refused_with_a_link_to_it(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    response = post_form(web, "/vehicles/new", "/vehicles/new", {**FORM, "registration_number": "bdg252qh"})
    assert response.status_code == 422
    assert "is already registered" in response.text
    assert 'href="/vehicles/BDG252QH"' in response.text


def test_finding_a_vehicle_ignores_case_spaces_and_hyphens(web: TestClient, study_vehicle: Vehicle) -> None:
    response = web.get("/vehicles/find?registration_number=bdg-252qh", follow_redirects=False)
    assert response.status_code == 303
    assert response.headers["location"] == "/vehicles/BDG252QH"


def test_an_unknown_registration_is_explained(web: TestClient) -> None:
    response = web.get("/vehicles/find?registration_number=xyz 1")
    assert response.status_code == 404
    assert "No vehicle XYZ 1 is registered" in response.text
    assert 'href="#registration_number"' in response.text


def test_an_unknown_vehicle_page_is_a_404_page(web: TestClient) -> None:
    response = web.get("/vehicles/NOPE1", headers={"accept": "text/html"})
    assert response.status_code == 404
    assert "<h1>Page not found</h1>" in response.text
    assert "No vehicle NOPE1 is registered" in response.text
