"""Every form carries a CSRF token; a POST without a valid one is refused with 403 and does nothing."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.inspections.models import Inspection
from app.vehicles.models import Vehicle
from web.webtools import OFFICER_EMAIL, PASSWORD, STUDY_READINGS, form_values, hidden, sign_in

VEHICLE = {
    "registration_number": "KJA 123 XY",
    "make": "Bajaj",
    "model": "RE",
    "wheelbase_m": "2.0",
    "driver_x_m": "0.93",
}


@pytest.mark.parametrize("token", [None, "", "not-the-token"])
def test_registering_a_vehicle_without_the_sessions_token_is_refused(
    web: TestClient, session: Session, token: str | None
) -> None:
    data = dict(VEHICLE) if token is None else {**VEHICLE, "csrf_token": token}
    response = web.post("/vehicles/new", data=data, follow_redirects=False)
    assert response.status_code == 403
    assert "nothing was saved" in response.text
    assert session.scalar(select(func.count()).select_from(Vehicle)) == 0


def test_another_sessions_token_is_refused(client: TestClient, officer: User, admin: User) -> None:
    sign_in(client, "admin@example.org")
    admin_token = hidden(client.get("/").text)
    client.cookies.clear()
    sign_in(client, OFFICER_EMAIL)
    response = client.post(
        "/vehicles/new", data={**VEHICLE, "csrf_token": admin_token}, follow_redirects=False
    )
    assert response.status_code == 403


def test_an_inspection_without_a_token_is_refused_and_not_stored(
    web: TestClient, session: Session, study_vehicle: Vehicle
) -> None:
    page = web.get("/vehicles/BDG252QH/inspections/new")
    data = {**form_values(page.text), **STUDY_READINGS}
    del data["csrf_token"]
    response = web.post("/vehicles/BDG252QH/inspections/new", data=data, follow_redirects=False)
    assert response.status_code == 403
    assert session.scalar(select(func.count()).select_from(Inspection)) == 0


def test_a_post_without_a_session_is_refused(client: TestClient) -> None:
    assert client.post("/vehicles/new", data=VEHICLE, follow_redirects=False).status_code == 403


def test_signing_in_without_the_forms_token_is_refused(client: TestClient, officer: User) -> None:
    client.get("/login")
    response = client.post(
        "/login", data={"email": OFFICER_EMAIL, "password": PASSWORD}, follow_redirects=False
    )
    assert response.status_code == 403
    assert "trikecert_session" not in client.cookies


def test_signing_in_with_a_token_but_not_its_cookie_is_refused(client: TestClient, officer: User) -> None:
    token = hidden(client.get("/login").text)
    client.cookies.clear()
    response = client.post(
        "/login",
        data={"email": OFFICER_EMAIL, "password": PASSWORD, "csrf_token": token},
        follow_redirects=False,
    )
    assert response.status_code == 403


def test_signing_out_needs_the_token_too(web: TestClient) -> None:
    assert web.post("/logout", data={"csrf_token": "forged"}, follow_redirects=False).status_code == 403
    assert web.get("/", follow_redirects=False).status_code == 200


def test_no_page_changes_anything_on_get(web: TestClient, study_vehicle: Vehicle) -> None:
    for url in ("/logout", "/admin/users/1/disable", "/vehicles/BDG252QH/inspections/new?front_kg_1=108"):
        web.get(url)
    assert web.get("/", follow_redirects=False).status_code == 200


def test_every_form_of_a_page_carries_the_token(web: TestClient, study_vehicle: Vehicle) -> None:
    for url in ("/", "/vehicles/new", "/vehicles/BDG252QH/inspections/new"):
        html = web.get(url).text
        assert html.count('method="post"') == html.count('name="csrf_token"')
        assert html.count('method="post"') >= 1
