"""Administrators add, edit, rotate the key of, disable and enable stations in the pages, and read the
settings in force; officers cannot; the key is shown once and never stored in clear."""

from __future__ import annotations

import re
from collections.abc import Iterator
from datetime import UTC, date, datetime, timedelta
from decimal import Decimal

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.accounts.models import UserSession
from app.config import Settings, get_settings
from app.stations.details import StationDetails
from app.stations.models import Station
from app.stations.service import create_station, hash_key
from app.stations.views import settings_rows
from app.web.models import FormSubmission
from web.webtools import form_values, hidden, post_form

INSPECTIONS = "/api/v1/inspections"
KEY = re.compile(r'<code id="station-key">(tks_[A-Za-z0-9_-]+)</code>')
NEW_STATION = {
    "name": "Agbara  weighbridge",
    "location": "Lagos-Badagry Expressway, Agbara",
    "operator_contact": "Mrs A. Okafor, +234 803 555 0100",
    "calibration_certificate": "SON/CAL/2026/0415",
    "valid_until_day": "31",
    "valid_until_month": "3",
    "valid_until_year": "2099",
    "capacity_kg": "3000",
    "division_kg": "1",
}


def api_status(client: TestClient, key: str) -> int:
    """The API's answer to a listing signed with this key."""
    status: int = client.get(INSPECTIONS, headers={"Authorization": f"Bearer {key}"}).status_code
    return status


def shown_key(html: str) -> str:
    found = KEY.search(html)
    assert found, "no key on the page"
    return found.group(1)


def stored(session: Session, station_id: int) -> Station:
    session.expire_all()
    station = session.get(Station, station_id)
    assert station is not None
    return station


def test_an_admin_adds_a_station_and_its_key_works_on_the_api(
    admin_web: TestClient, session: Session
) -> None:
    response = post_form(admin_web, "/admin/stations/new", "/admin/stations/new", NEW_STATION)

    assert response.status_code == 200
    assert "it will not be shown again" in response.text
    assert response.headers["cache-control"] == "no-store"
    key = shown_key(response.text)
    assert api_status(admin_web, key) == 200
    station = session.scalars(select(Station).where(Station.name == "Agbara weighbridge")).one()
    assert (station.location, station.operator_contact) == (
        NEW_STATION["location"],
        NEW_STATION["operator_contact"],
    )
    assert station.calibration_certificate == "SON/CAL/2026/0415"
    assert station.calibration_valid_until == date(2099, 3, 31)
    assert (station.capacity_kg, station.division_kg) == (Decimal(3000), Decimal(1))
    assert station.key_hash == hash_key(key)
    # The key is kept nowhere in clear: not on the station, not in a flash, not as a form's result.
    assert key not in (station.key_hash, station.key_prefix)
    assert all(key not in (s.flash or "") for s in session.scalars(select(UserSession)))
    assert all(key not in f.redirect_path for f in session.scalars(select(FormSubmission)))
    page = admin_web.get("/admin/stations")
    assert "Agbara weighbridge" in page.text
    assert key not in page.text
    assert key not in admin_web.get(f"/admin/stations/{station.id}").text


def test_sending_the_add_form_twice_adds_one_station_and_shows_the_key_once(
    admin_web: TestClient, session: Session
) -> None:
    page = admin_web.get("/admin/stations/new")
    fields = {**form_values(page.text), **NEW_STATION}
    first = admin_web.post("/admin/stations/new", data=fields, follow_redirects=False)
    again = admin_web.post("/admin/stations/new", data=fields, follow_redirects=False)

    assert first.status_code == 200
    assert again.status_code == 303
    assert again.headers["location"] == "/admin/stations"
    follow = admin_web.get("/admin/stations")
    assert "A station key is shown only once" in follow.text
    assert shown_key(first.text) not in follow.text
    assert len(session.scalars(select(Station)).all()) == 1


def test_adding_a_station_with_problems_shows_them_and_stores_nothing(
    admin_web: TestClient, session: Session
) -> None:
    response = post_form(
        admin_web,
        "/admin/stations/new",
        "/admin/stations/new",
        {
            **NEW_STATION,
            "name": " ",
            "capacity_kg": "three tonnes",
            "valid_until_day": "31",
            "valid_until_month": "2",
        },
    )

    assert response.status_code == 422
    assert "<title>Error: Add a station" in response.text
    assert '<a href="#name">Enter the station' in response.text
    assert '<a href="#capacity_kg">Enter the capacity as a number of kilograms' in response.text
    assert (
        '<a href="#valid_until_day">The calibration&#39;s valid-until date must be a real date'
        in response.text
    )
    assert 'id="capacity_kg-error"' in response.text
    assert 'value="three tonnes"' in response.text
    assert 'value="Lagos-Badagry Expressway, Agbara"' in response.text
    assert session.scalars(select(Station)).all() == []


def test_a_second_station_of_the_same_name_is_refused_beside_the_name(
    admin_web: TestClient, station: Station, session: Session
) -> None:
    response = post_form(
        admin_web, "/admin/stations/new", "/admin/stations/new", {**NEW_STATION, "name": "Ojota weighbridge"}
    )

    assert response.status_code == 422
    assert '<a href="#name">A station named' in response.text
    assert len(session.scalars(select(Station)).all()) == 1


def test_an_admin_edits_a_station(admin_web: TestClient, station: Station, session: Session) -> None:
    url = f"/admin/stations/{station.id}"
    response = post_form(
        admin_web,
        url,
        url,
        {"name": "Ojota weighbridge 2", "location": "", "valid_until_day": "1", "capacity_kg": "2500,5"},
    )

    assert response.status_code == 303
    assert response.headers["location"] == url
    saved = stored(session, station.id)
    assert saved.name == "Ojota weighbridge 2"
    assert saved.location is None
    assert saved.calibration_valid_until == date(2099, 1, 1)
    assert saved.capacity_kg == Decimal("2500.5")
    page = admin_web.get(url)
    assert "The details of Ojota weighbridge 2 were saved." in page.text
    assert "were saved" not in admin_web.get(url).text  # the message is shown once


def test_an_invalid_edit_shows_every_problem_keeps_the_values_and_stores_nothing(
    admin_web: TestClient, station: Station, session: Session
) -> None:
    url = f"/admin/stations/{station.id}"
    response = post_form(
        admin_web,
        url,
        url,
        {"name": "", "location": "Somewhere else", "capacity_kg": "abc", "division_kg": "1O"},
    )

    assert response.status_code == 422
    text = response.text
    assert 'class="error-summary"' in text
    for input_id in ("name", "capacity_kg", "division_kg"):
        assert f'<a href="#{input_id}">' in text
        assert f'id="{input_id}-error"' in text
        assert f'aria-describedby="{input_id}-hint {input_id}-error"' in text
    assert 'value="abc"' in text
    assert 'value="1O"' in text
    assert 'value="Somewhere else"' in text
    saved = stored(session, station.id)
    assert (saved.name, saved.location) == ("Ojota weighbridge", "Ojota, Lagos")
    assert saved.capacity_kg == Decimal(3000)


def test_a_division_larger_than_the_capacity_is_refused(
    admin_web: TestClient, station: Station, session: Session
) -> None:
    url = f"/admin/stations/{station.id}"
    response = post_form(admin_web, url, url, {"capacity_kg": "100", "division_kg": "200"})

    assert response.status_code == 422
    assert '<a href="#division_kg">The division (e) must not be larger than the capacity</a>' in response.text
    assert stored(session, station.id).capacity_kg == 3000


def test_a_service_rule_is_shown_beside_its_field(
    admin_web: TestClient, station: Station, session: Session
) -> None:
    url = f"/admin/stations/{station.id}"
    response = post_form(admin_web, url, url, {"division_kg": "0.0001"})

    assert response.status_code == 422
    assert '<a href="#division_kg">Give the weight to at most 3 decimal places</a>' in response.text
    assert stored(session, station.id).division_kg == 1


def test_half_a_date_is_refused_naming_what_is_missing(admin_web: TestClient, station: Station) -> None:
    url = f"/admin/stations/{station.id}"
    response = post_form(admin_web, url, url, {"valid_until_month": "", "valid_until_year": ""})

    assert response.status_code == 422
    assert (
        '<a href="#valid_until_month">The date the calibration is valid until must include a month and year'
        in (response.text)
    )


def test_rotating_the_key_stops_the_old_one_at_once(admin_web: TestClient, session: Session) -> None:
    station, old_key = create_station(session, name="Ikeja weighbridge")
    assert api_status(admin_web, old_key) == 200
    page = admin_web.get(f"/admin/stations/{station.id}")
    fields = {"csrf_token": hidden(page.text), "form_token": hidden(page.text, "form_token")}

    response = admin_web.post(f"/admin/stations/{station.id}/key", data=fields, follow_redirects=False)

    assert response.status_code == 200
    assert "it will not be shown again" in response.text
    assert "The old key no longer works." in response.text
    new_key = shown_key(response.text)
    assert api_status(admin_web, old_key) == 401
    assert api_status(admin_web, new_key) == 200
    assert stored(session, station.id).key_rotated_at is not None

    again = admin_web.post(f"/admin/stations/{station.id}/key", data=fields, follow_redirects=False)
    assert again.status_code == 303
    assert api_status(admin_web, new_key) == 200  # a resent form does not rotate again
    assert "A station key is shown only once" in admin_web.get(again.headers["location"]).text


def test_disabling_refuses_the_key_and_enabling_restores_it(admin_web: TestClient, session: Session) -> None:
    station, key = create_station(session, name="Ikeja weighbridge")
    token = hidden(admin_web.get(f"/admin/stations/{station.id}").text)

    response = admin_web.post(
        f"/admin/stations/{station.id}/disable", data={"csrf_token": token}, follow_redirects=False
    )
    assert response.status_code == 303
    assert api_status(admin_web, key) == 401
    page = admin_web.get(f"/admin/stations/{station.id}")
    assert "Ikeja weighbridge is disabled: its key is refused" in page.text
    assert ">Enable</button>" in page.text
    assert "Disabled" in admin_web.get("/admin/stations").text

    response = admin_web.post(
        f"/admin/stations/{station.id}/enable", data={"csrf_token": token}, follow_redirects=False
    )
    assert response.status_code == 303
    assert api_status(admin_web, key) == 200
    assert (
        "Ikeja weighbridge is enabled: its key works again."
        in admin_web.get(f"/admin/stations/{station.id}").text
    )


def test_the_list_says_in_words_when_a_calibration_has_lapsed(
    admin_web: TestClient, session: Session
) -> None:
    yesterday = datetime.now(UTC).date() - timedelta(days=1)
    create_station(session, name="Lapsed scale", details=StationDetails(calibration_valid_until=yesterday))
    create_station(session, name="Unknown scale")

    page = admin_web.get("/admin/stations")

    assert page.status_code == 200
    row = page.text.split("Lapsed scale")[1].split("</tr>")[0]
    assert ">Lapsed</strong>" in row
    assert "Not on record" in page.text.split("Unknown scale")[1]
    assert ">Stations</a>" in page.text
    assert 'href="/admin/stations" aria-current="page"' in page.text


ADMIN_PAGES = ["/admin/stations", "/admin/stations/new", "/admin/stations/{id}", "/admin/settings"]
ADMIN_POSTS = [
    "/admin/stations/new",
    "/admin/stations/{id}",
    "/admin/stations/{id}/key",
    "/admin/stations/{id}/disable",
    "/admin/stations/{id}/enable",
]


def test_officers_get_403_on_every_station_and_settings_page(
    web: TestClient, station: Station, session: Session
) -> None:
    for url in ADMIN_PAGES:
        response = web.get(url.format(id=station.id))
        assert response.status_code == 403, url
        assert "Only an administrator" in response.text
    token = hidden(web.get("/").text)
    for url in ADMIN_POSTS:
        response = web.post(
            url.format(id=station.id), data={**NEW_STATION, "csrf_token": token}, follow_redirects=False
        )
        assert response.status_code == 403, url
    assert ">Stations</a>" not in web.get("/").text
    saved = stored(session, station.id)
    assert (saved.name, saved.active, saved.key_rotated_at) == ("Ojota weighbridge", True, None)
    assert len(session.scalars(select(Station)).all()) == 1


def test_a_post_without_the_csrf_token_is_refused_and_changes_nothing(
    admin_web: TestClient, station: Station, session: Session
) -> None:
    for url in ADMIN_POSTS:
        response = admin_web.post(url.format(id=station.id), data=NEW_STATION, follow_redirects=False)
        assert response.status_code == 403, url
        response = admin_web.post(
            url.format(id=station.id), data={**NEW_STATION, "csrf_token": "forged"}, follow_redirects=False
        )
        assert response.status_code == 403, url
    saved = stored(session, station.id)
    assert (saved.name, saved.active, saved.key_rotated_at) == ("Ojota weighbridge", True, None)
    assert len(session.scalars(select(Station)).all()) == 1


def test_an_unknown_station_is_404(admin_web: TestClient) -> None:
    assert admin_web.get("/admin/stations/999999").status_code == 404
    assert admin_web.get("/admin/stations/abc", headers={"Accept": "text/html"}).status_code == 404


SIGNING_SEED = "bXktdmVyeS1zZWNyZXQtc2lnbmluZy1rZXktMzJieXQ="


@pytest.fixture
def secret_settings(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """The settings with a signing key and a non-default occupant mass in the environment."""
    monkeypatch.setenv("TRIKECERT_SIGNING_KEY", SIGNING_SEED)
    monkeypatch.setenv("TRIKECERT_OCCUPANT_MASS_KG", "75")
    get_settings.cache_clear()
    yield
    monkeypatch.undo()
    get_settings.cache_clear()


def test_the_settings_page_lists_the_settings_in_force_and_no_secret(
    admin_web: TestClient, secret_settings: None
) -> None:
    page = admin_web.get("/admin/settings")

    assert page.status_code == 200
    text = page.text
    for variable in (
        "TRIKECERT_OCCUPANT_MASS_KG",
        "TRIKECERT_SUM_TOLERANCE",
        "TRIKECERT_MAX_READING_SPREAD_KG",
        "TRIKECERT_CERTIFICATE_VALIDITY_MONTHS",
        "TRIKECERT_STATION_RATE_LIMIT",
        "TRIKECERT_SESSION_IDLE_MINUTES",
        "TRIKECERT_SESSION_ABSOLUTE_HOURS",
        "TRIKECERT_DISPLAY_TIMEZONE",
    ):
        assert f"<code>{variable.replace('_', '_<wbr>')}</code>" in text
    assert "75 kg</td>" in text
    assert "72 kg" not in text
    assert "0.01 (1.0 %) (default)" in text
    for variable, shown in (
        ("TRIKECERT_MFA", "optional (default)"),
        ("TRIKECERT_BASE_URL", f"{get_settings().base_url} (default)"),
        ("TRIKECERT_BALLAST_X_M", "0.3 m (default)"),
        ("TRIKECERT_MIN_ROLLOVER_G", "Not set (default)"),
        ("TRIKECERT_AIR_DENSITY_KG_M3", "1.2 kg/m³ (default)"),
    ):
        assert f"<code>{variable.replace('_', '_<wbr>')}</code>" in text
        assert f"{shown}</td>" in text, variable
    assert get_settings().display_timezone in text
    assert SIGNING_SEED not in text
    assert "TRIKECERT_SIGNING_KEY" not in text
    assert "TRIKECERT_DATABASE_URL" not in text
    assert get_settings().database_url not in text


def test_the_settings_rows_never_carry_a_secret() -> None:
    settings = Settings(
        database_url="postgresql+psycopg://trikecert:Very-Secret-Password-1@db/trikecert",
        signing_key=SIGNING_SEED,
    )
    shown = repr(settings_rows(settings))
    assert "Very-Secret-Password-1" not in shown
    assert SIGNING_SEED not in shown
    assert "DATABASE" not in shown
