"""The services' refusals a page shows (a type assessment with too few vehicles, a wrong or locked-out
second-factor code, a station's name taken) speak the page's language, with their figures, plates
and names as they are; the JSON API keeps them English."""

from __future__ import annotations

import html
import re

import pytest
from fastapi.testclient import TestClient
from httpx2 import Response

from app.accounts.models import User
from app.stations.models import Station
from web.webtools import OFFICER_EMAIL, code_at, enrol, hidden, post_form, sign_in

LANGUAGES = ["ha", "yo", "ig", "pcm"]


def visible(page: str) -> str:
    """The text a reader sees (tags dropped, entities read), with runs of spaces made one."""
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", page)).split())


# The study's vehicle is registered but not weighed: no inspection of its model to assess.
TOO_FEW = {
    "ha": "Kimanta samfuri yana buƙatar binciken abubuwan hawa aƙalla biyu na Bajaj RE; an samu 0",
    "yo": "Ìṣàyẹ̀wò àwòṣe nílò àyẹ̀wò ọkọ̀ méjì ó kéré tán ti Bajaj RE; a rí 0",
    "ig": "Ntụle ụdị chọrọ nlele ụgbọala abụọ ma ọ dịkarịa ala nke Bajaj RE; a hụrụ 0",
    "pcm": "Type assessment need inspection of at least two motors of di Bajaj RE; we find 0",
}


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_model_with_one_vehicle_is_refused_in_the_chosen_language(
    web: TestClient, study_vehicle: object, language: str
) -> None:
    english = visible(web.get("/type-assessments/new", params={"make": "Bajaj", "model": "RE"}).text)
    assert "A type assessment needs inspections of at least two vehicles of the Bajaj RE; found 0" in english

    web.cookies.set("trikecert_lang", language)
    page = web.get("/type-assessments/new", params={"make": "Bajaj", "model": "RE"})
    assert page.status_code == 200
    text = visible(page.text)
    assert TOO_FEW[language] in text
    assert "at least two vehicles" not in text


def enter_code(client: TestClient, code: str) -> Response:
    page = client.get("/login/code")
    response: Response = client.post(
        "/login/code",
        data={"csrf_token": hidden(page.text), "next": "/", "code": code},
        follow_redirects=False,
    )
    return response


WRONG_CODE = {
    "ha": "Wannan lambar ba daidai ba ce ko an riga an yi amfani da ita",
    "yo": "Kóòdù yẹn kò tọ́ tàbí a ti lò ó tẹ́lẹ̀",
    "ig": "Koodu ahụ ezighi ezi ma ọ bụ e jirila ya mee ihe",
    "pcm": "Dat code no correct or dem don use am before",
}
LOCKED_OUT = {
    "ha": "Lambobi marasa daidai sun yi yawa; jira minti 15",
    "yo": "Kóòdù tí kò tọ́ ti pọ̀ jù; dúró fún ìṣẹ́jú 15",
    "ig": "Koodu ezighi ezi dị ukwuu; chere nkeji 15",
    "pcm": "Too many wrong codes; wait 15 minutes, then try again",
}


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_wrong_code_is_refused_in_the_chosen_language(
    client: TestClient, officer: User, required: None, language: str
) -> None:
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    secret, _codes = enrol(client)
    client.cookies.clear()
    client.cookies.set("trikecert_lang", language)
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    wrong = "123456" if code_at(secret) != "123456" else "654321"

    refused = enter_code(client, wrong)
    assert refused.status_code == 422
    assert WRONG_CODE[language] in visible(refused.text)
    assert "That code is not right" not in refused.text
    for _ in range(4):
        enter_code(client, wrong)
    locked = enter_code(client, code_at(secret, 1))
    assert locked.status_code == 422
    assert LOCKED_OUT[language] in visible(locked.text)
    if language != "pcm":  # Pidgin says it as English does
        assert "Too many wrong codes" not in locked.text


TAKEN = {
    "ha": "Akwai tasha mai suna 'Ojota weighbridge' tuni",
    "yo": "Ibùdó tí a ń pè ní 'Ojota weighbridge' ti wà tẹ́lẹ̀",
    "ig": "Ọdụ aha ya bụ 'Ojota weighbridge' adịlarị",
    "pcm": "Station wey dem call 'Ojota weighbridge' don dey already",
}


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_station_name_taken_is_refused_in_the_chosen_language(
    admin_web: TestClient, station: Station, language: str
) -> None:
    admin_web.cookies.set("trikecert_lang", language)
    refused = post_form(
        admin_web, "/admin/stations/new", "/admin/stations/new", {"name": "Ojota weighbridge"}
    )
    assert refused.status_code == 422
    text = visible(refused.text)
    assert TAKEN[language] in text
    assert "already exists" not in text
