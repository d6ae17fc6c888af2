"""The last English on the officer pages: how a page names a person (an account without a name, a
badge) and the second factor's QR code, in the reader's language; documents keep the English."""

from __future__ import annotations

import html
import re

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.accounts.models import User
from web.webtools import OFFICER_EMAIL, STUDY_READINGS, code_at, hidden, post_form, sign_in

VEHICLE = {
    "registration_number": "BDG 252 QH",
    "make": "Bajaj",
    "model": "RE",
    "model_year": "2012",
    "wheelbase_m": "2.000",
    "driver_x_m": "0.9303",
    "passenger_x_m_1": "1.6303",
}
FORM_URL = "/vehicles/BDG252QH/inspections/new"
# A person as the inspection page names them: without a name, then with a badge.
UNNAMED = {
    "ha": "Jami'i na {id} (babu suna a rubuce)",
    "yo": "Òṣìṣẹ́ nọ́mbà {id} (kò sí orúkọ lákọsílẹ̀)",
    "ig": "Onye ọrụ nọmba {id} (enweghị aha e dekọrọ)",
    "pcm": "Officer no. {id} (no name for record)",
}
BADGE = {
    "ha": "Amina Bello (baji 4471)",
    "yo": "Amina Bello (báàjì 4471)",
    "ig": "Amina Bello (baajị 4471)",
    "pcm": "Amina Bello (badge 4471)",
}
QR_TITLE = {
    "ha": "Lambar QR don saita mataki na biyu",
    "yo": "Kóòdù QR fún ìṣètò ìgbésẹ̀ kejì",
    "ig": "Koodu QR maka idozi nzọụkwụ nke abụọ",
    "pcm": "QR code to set up second factor",
}


def recorded_by(page: str) -> str:
    """Who recorded the weighing, as the inspection page shows it."""
    found = re.search(r'id="recorded-by">(.*?)</dd>', page, re.S)
    assert found, page
    return html.unescape(found[1]).strip()


@pytest.mark.parametrize("language", ["ha", "yo", "ig", "pcm"])
def test_the_inspection_page_names_the_officer_in_the_chosen_language(
    web: TestClient, session: Session, officer: User, language: str
) -> None:
    assert post_form(web, "/vehicles/new", "/vehicles/new", VEHICLE).status_code == 303
    stored = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS)
    assert stored.status_code == 303
    path = stored.headers["location"]
    assert recorded_by(web.get(path).text) == f"Officer no. {officer.id} (no name on record)"

    web.cookies.set("trikecert_lang", language)
    assert recorded_by(web.get(path).text) == UNNAMED[language].format(id=officer.id)

    officer.display_name, officer.badge_number = "Amina Bello", "4471"
    session.commit()
    assert recorded_by(web.get(path).text) == BADGE[language]
    assert officer.shown_as() == "Amina Bello (badge 4471)"  # as documents name her: the binding English
    web.cookies.set("trikecert_lang", "en")
    assert recorded_by(web.get(path).text) == "Amina Bello (badge 4471)"


@pytest.mark.parametrize("language", ["ha", "yo", "ig", "pcm"])
def test_the_second_factor_pages_name_the_qr_code_in_the_chosen_language(
    client: TestClient, officer: User, required: None, language: str
) -> None:
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    assert "<title>Enrolment QR code</title>" in client.get("/account/two-factor").text

    client.cookies.set("trikecert_lang", language)
    page = client.get("/account/two-factor")
    assert page.status_code == 200
    assert f"<title>{html.escape(QR_TITLE[language], quote=False)}</title>" in page.text
    assert "Enrolment QR code" not in page.text
    secret = re.search(r'<code id="secret" class="secret">([A-Z2-7]+)</code>', page.text)
    assert secret is not None
    form = {"csrf_token": hidden(page.text), "next": "/", "code": code_at(secret[1], -1)}
    codes = client.post("/account/two-factor", data=form)
    assert codes.status_code == 200
    enrolled = client.get("/account/two-factor").text
    client.cookies.clear()
    client.cookies.set("trikecert_lang", language)
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    code_page = client.get("/login/code").text
    # None of the four pages keeps a sentence of its English.
    english = ["Enter your code", "recovery code", "authenticator app", "Your second factor", "They are"]
    for shown in (page.text, codes.text, enrolled, code_page):
        assert [words for words in english if words in shown and language != "pcm"] == []
