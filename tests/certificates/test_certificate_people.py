"""Who stands behind a document (issue 9, item 5): officers have a name and a badge; the PDF and the
officers' pages name who recorded the weighing and who issued the document by them, never by email;
the scale's calibration is printed whenever any of it is known; and TRIKECERT_REQUIRE_CALIBRATION
refuses to issue for a weighing with none."""

from __future__ import annotations

import html
import io
import re
from collections.abc import Callable, Iterator
from datetime import date
from typing import Any

import pytest
from certificate_helpers import INSPECTIONS, certify, register, weigh
from fastapi.testclient import TestClient
from pypdf import PdfReader
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from web.webtools import OFFICER_EMAIL, PASSWORD, STUDY_READINGS, hidden, post_form, sign_in

from app import config
from app.accounts.models import User
from app.accounts.service import create_user
from app.certificates.models import Certificate
from app.cli import main
from app.stations.details import StationDetails
from app.stations.service import create_station

NAME = "Amina Bello"
BADGE = "NSCDC/4471"
SHOWN = f"{NAME} (badge {BADGE})"
CALIBRATED = StationDetails(
    calibration_certificate="SON/CAL/2026/0415", calibration_valid_until=date(2099, 3, 31)
)
FORM_URL = "/vehicles/BDG252QH/inspections/new"


def text_of(pdf: bytes) -> str:
    return " ".join(PdfReader(io.BytesIO(pdf)).pages[0].extract_text().split())


def station_client(client: TestClient, session: Session, name: str, details: StationDetails) -> TestClient:
    """A client signed as a new station with these scale details."""
    _station, key = create_station(session, name=name, details=details)
    station = TestClient(client.app, raise_server_exceptions=False)
    station.headers["Authorization"] = f"Bearer {key}"
    return station


@pytest.fixture
def officer_web(client: TestClient, session: Session) -> TestClient:
    """The client signed in as an officer with a name and a badge."""
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer", name=NAME, badge=BADGE)
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    return client


@pytest.fixture
def require_calibration(monkeypatch: pytest.MonkeyPatch) -> Iterator[Callable[[], None]]:
    """A switch that turns TRIKECERT_REQUIRE_CALIBRATION on for the rest of the test."""

    def turn_on() -> None:
        monkeypatch.setenv("TRIKECERT_REQUIRE_CALIBRATION", "true")
        config.get_settings.cache_clear()

    yield turn_on
    monkeypatch.undo()
    config.get_settings.cache_clear()


def issue_from_page(web: TestClient, inspection_id: int) -> str:
    """Issue from the inspection's page; the certificate's page address."""
    token = hidden(web.get(f"/inspections/{inspection_id}").text)
    issued = web.post(
        f"/inspections/{inspection_id}/certificate", data={"csrf_token": token}, follow_redirects=False
    )
    assert issued.status_code == 303
    location: str = issued.headers["location"]
    assert location.startswith("/certificates/TRK-"), location
    return location


def record_from_page(web: TestClient) -> int:
    """The officer records the study's readings on the page; the inspection's id."""
    response = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS)
    assert response.status_code == 303, response.text
    return int(response.headers["location"].rsplit("/", 1)[1])


def test_an_officers_own_weighing_names_them_by_name_and_badge_on_the_pdf_and_the_pages(
    client: TestClient, session: Session, officer_web: TestClient
) -> None:
    register(station_client(client, session, "Test weighbridge", StationDetails()))
    inspection_id = record_from_page(officer_web)
    inspection_page = officer_web.get(f"/inspections/{inspection_id}").text
    assert re.search(rf'id="recorded-by">{re.escape(SHOWN)}<', inspection_page)
    location = issue_from_page(officer_web, inspection_id)

    page = officer_web.get(location).text
    assert f"<dt>Weighing recorded by</dt><dd>{SHOWN}</dd>" in page
    assert f"<dt>Issued by</dt><dd>{SHOWN}</dd>" in page
    assert "<dt>Scale calibration</dt><dd>Not recorded</dd>" in page
    pdf = text_of(officer_web.get(f"{location}/pdf").content)
    assert f"Recorded by {SHOWN}" in pdf
    assert f"Issued by {SHOWN}" in pdf
    assert "Scale calibration Not recorded" in pdf  # weighed without a station: truly none
    own_header = f'<span class="header__user">{OFFICER_EMAIL}</span>'  # the signed-in officer's own
    for text in (page, pdf, officer_web.get(f"/inspections/{inspection_id}").text):
        assert OFFICER_EMAIL not in text.replace(own_header, "")
    assert "none (station submission)" not in pdf


def test_a_station_weighing_issued_by_an_officer_names_both_and_prints_the_calibration(
    client: TestClient, session: Session, officer_web: TestClient
) -> None:
    station = station_client(client, session, "Agbara weighbridge", CALIBRATED)
    register(station)
    inspection_id = weigh(station)
    inspection_page = officer_web.get(f"/inspections/{inspection_id}").text
    assert 'id="recorded-by">Agbara weighbridge, weighbridge station<' in inspection_page
    assert 'id="calibration">SON/CAL/2026/0415, valid until 31 March 2099<' in inspection_page

    location = issue_from_page(officer_web, inspection_id)
    pdf = text_of(officer_web.get(f"{location}/pdf").content)
    assert "Recorded by Agbara weighbridge, weighbridge station" in pdf
    assert f"Issued by {SHOWN}" in pdf
    assert "Scale calibration SON/CAL/2026/0415, valid until 31 March 2099" in pdf
    assert "none (station submission)" not in pdf
    assert f"issued by {SHOWN}" in officer_web.get(f"/inspections/{inspection_id}").text


@pytest.mark.parametrize(
    ("details", "printed"),
    [
        (StationDetails(), "Scale calibration Not recorded"),
        (
            StationDetails(calibration_valid_until=date(2099, 3, 31)),
            "Scale calibration valid until 31 March 2099 (certificate number not recorded)",
        ),
        (
            StationDetails(calibration_certificate="SON/CAL/2026/0415"),
            "Scale calibration SON/CAL/2026/0415 (validity not recorded)",
        ),
    ],
)
def test_a_station_that_certifies_its_own_weighing_is_named_as_the_issuer(
    client: TestClient, session: Session, details: StationDetails, printed: str
) -> None:
    station = station_client(client, session, "Ikeja weighbridge", details)
    register(station)
    number = certify(station, weigh(station))["number"]
    pdf = text_of(station.get(f"/api/v1/certificates/{number}/pdf").content)
    assert "Recorded by Ikeja weighbridge, weighbridge station" in pdf
    assert "Issued by Ikeja weighbridge, weighbridge station" in pdf
    assert printed in pdf


def _certificates(session: Session) -> int:
    session.expire_all()
    return session.scalar(select(func.count()).select_from(Certificate)) or 0


def test_with_calibration_required_a_weighing_without_one_gets_no_document(
    client: TestClient, session: Session, officer_web: TestClient, require_calibration: Callable[[], None]
) -> None:
    # Weighed before the setting was turned on (the station would be refused now), and by the
    # officer on the page (no station, so no scale calibration at all).
    api = station_client(client, session, "Test weighbridge", StationDetails())
    register(api)
    by_station = weigh(api)
    by_officer = record_from_page(officer_web)
    require_calibration()

    refused = api.post(f"{INSPECTIONS}/{by_station}/certificate")
    assert refused.status_code == 403
    problem = refused.json()["errors"][0]
    assert (problem["field"], problem["rule"]) == ("inspection_id", "calibration_missing")
    assert "Test weighbridge had no calibration on record" in problem["message"]
    assert "TRIKECERT_REQUIRE_CALIBRATION" in problem["message"]

    token = hidden(officer_web.get(f"/inspections/{by_officer}").text)
    answer = officer_web.post(f"/inspections/{by_officer}/certificate", data={"csrf_token": token})
    assert answer.status_code == 200
    assert "recorded without a station, so no scale calibration is on record" in answer.text
    assert _certificates(session) == 0


def test_with_calibration_required_a_calibrated_weighing_is_certified(
    client: TestClient, session: Session, require_calibration: Callable[[], None]
) -> None:
    require_calibration()
    station = station_client(client, session, "Agbara weighbridge", CALIBRATED)
    register(station)
    certify(station, weigh(station))
    assert _certificates(session) == 1


def test_the_settings_page_says_calibration_is_required_for_issue(
    client: TestClient, session: Session
) -> None:
    create_user(session, email="admin@example.org", password=PASSWORD, role="admin", name="Ada Obi")
    assert sign_in(client, "admin@example.org").status_code == 303
    page = client.get("/admin/settings")
    assert page.status_code == 200
    assert "no certificate or refusal is issued for a weighing without one" in page.text


# ---- accounts: the command line and the administrator's pages --------------------------------------


def test_create_user_on_the_command_line_takes_a_name_and_a_badge(
    session: Session, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO(f"{PASSWORD}\n"))
    code = main(
        [
            "create-user",
            "ngozi@example.org",
            "--role",
            "officer",
            "--name",
            " Ngozi  Eze ",
            "--badge",
            "FRSC 12",
        ]
    )
    assert code == 0
    assert "Ngozi Eze (badge FRSC 12)" in capsys.readouterr().out
    user = session.scalar(select(User).where(User.email == "ngozi@example.org"))
    assert user is not None
    assert (user.display_name, user.badge_number) == ("Ngozi Eze", "FRSC 12")


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ([], "the following arguments are required: --name"),
        (["--name", "   "], "name: enter the person's name"),
        (["--name", "Ngozi", "--badge", "12;DROP"], "badge: use up to 32 letters"),
        (["--name", "N" * 101], "name: keep the name to 100 characters"),
    ],
)
def test_create_user_refuses_a_missing_or_bad_name_or_badge(
    session: Session,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    extra: list[str],
    message: str,
) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO(f"{PASSWORD}\n"))
    try:
        code = main(["create-user", "ngozi@example.org", "--role", "officer", *extra])
    except SystemExit as exit_:
        code = int(str(exit_.code))
    assert code == 2
    assert message in capsys.readouterr().err
    assert session.scalar(select(User).where(User.email == "ngozi@example.org")) is None


@pytest.fixture
def admin_pages(client: TestClient, session: Session) -> TestClient:
    """The client signed in as an administrator."""
    create_user(session, email="admin@example.org", password=PASSWORD, role="admin", name="Ada Obi")
    assert sign_in(client, "admin@example.org").status_code == 303
    return client


def _new_user(fields: dict[str, str]) -> dict[str, str]:
    return {"email": "ngozi@example.org", "role": "officer", "password": "a long enough secret", **fields}


def test_an_admin_adds_an_officer_with_a_name_and_badge_and_then_changes_them(
    admin_pages: TestClient, session: Session
) -> None:
    added = post_form(
        admin_pages,
        "/admin/users/new",
        "/admin/users/new",
        _new_user({"name": "Ngozi Eze", "badge": "FRSC 12"}),
    )
    assert added.status_code == 303
    users = admin_pages.get("/admin/users").text
    assert '<td data-label="Name">Ngozi Eze</td>' in users
    assert '<td data-label="Badge">FRSC 12</td>' in users
    user = session.scalar(select(User).where(User.email == "ngozi@example.org"))
    assert user is not None
    edit = f"/admin/users/{user.id}/edit"
    assert f'href="{edit}"' in users

    changed = post_form(admin_pages, edit, edit, {"name": "Ngozi Eze-Okafor", "badge": ""})
    assert changed.status_code == 303
    session.expire_all()
    assert (user.display_name, user.badge_number) == ("Ngozi Eze-Okafor", None)
    assert "is now shown as Ngozi Eze-Okafor." in admin_pages.get("/admin/users").text


@pytest.mark.parametrize(
    ("fields", "field", "message"),
    [
        ({"name": ""}, "name", "Enter the person"),
        ({"name": "N" * 101}, "name", "Keep the name to 100 characters"),
        ({"name": "Ngozi\u200bEze"}, "name", "Remove the invisible character U+200B"),
        ({"name": "Ngozi Eze", "badge": "<b>12</b>"}, "badge", "Use up to 32 letters"),
    ],
)
def test_adding_or_editing_with_a_bad_name_or_badge_shows_the_rule_beside_the_field(
    admin_pages: TestClient, session: Session, fields: dict[str, Any], field: str, message: str
) -> None:
    added = post_form(admin_pages, "/admin/users/new", "/admin/users/new", _new_user(fields))
    assert added.status_code == 422
    assert f'<a href="#{field}">{message}' in added.text
    assert f'id="{field}-error"' in added.text
    assert session.scalar(select(User).where(User.email == "ngozi@example.org")) is None

    user = create_user(
        session, email="ngozi@example.org", password=PASSWORD, role="officer", name="Ngozi Eze"
    )
    edit = f"/admin/users/{user.id}/edit"
    refused = post_form(admin_pages, edit, edit, {"badge": "", **fields})
    assert refused.status_code == 422
    assert f'<a href="#{field}">{message}' in refused.text
    session.expire_all()
    assert (user.display_name, user.badge_number) == ("Ngozi Eze", None)


def test_an_account_made_before_names_is_shown_without_its_email(
    session: Session, client: TestClient
) -> None:
    legacy = create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    register(station_client(client, session, "Test weighbridge", StationDetails()))
    inspection_id = record_from_page(client)
    page = client.get(f"/inspections/{inspection_id}").text
    assert f'id="recorded-by">Officer no. {legacy.id} (no name on record)<' in page


@pytest.mark.parametrize(
    ("language", "station_words", "gap"),
    [
        ("ha", "Ikeja weighbridge, tashar ma'aunin nauyi", "Ba a rubuta ba"),
        ("yo", "Ikeja weighbridge, ibùdó òṣùwọ̀n ọkọ̀", "A kò kọ ọ́ sílẹ̀"),
        ("ig", "Ikeja weighbridge, ọdụ ihe ọtụtụ ibu ụgbọala", "Edebeghị ya"),
        ("pcm", "Ikeja weighbridge, weighbridge station", "Dem no record am"),
    ],
)
def test_the_pages_name_a_station_and_a_gap_in_the_chosen_language(
    client: TestClient,
    session: Session,
    officer_web: TestClient,
    language: str,
    station_words: str,
    gap: str,
) -> None:
    station = station_client(client, session, "Ikeja weighbridge", StationDetails())
    register(station)
    inspection_id = weigh(station)
    number = certify(station, inspection_id)["number"]

    officer_web.cookies.set("trikecert_lang", language)
    inspection_page = html.unescape(officer_web.get(f"/inspections/{inspection_id}").text)
    assert f'id="recorded-by">{station_words}<' in inspection_page
    page = html.unescape(officer_web.get(f"/certificates/{number}").text)
    assert page.count(f"<dd>{station_words}</dd>") == 2  # recorded by and issued by
    assert f"<dd>{gap}</dd>" in page
    assert "Not recorded" not in page
    # The paper's binding English names the station as it always did.
    pdf = text_of(officer_web.get(f"/certificates/{number}/pdf").content)
    assert "Recorded by Ikeja weighbridge, weighbridge station" in pdf
