"""The officer pages speak the language the officer chose (cookie trikecert_lang): Hausa, Yoruba,
Igbo or Nigerian Pidgin, with none of the page's English sentences left over."""

from __future__ import annotations

import html
import re

import pytest
from fastapi.testclient import TestClient

from app.accounts.models import User
from app.stations.models import Station

LANGUAGES = ["ha", "yo", "ig", "pcm"]

# Per page: a characteristic translation per language (the glossary's, docs/translations.md), and English sentences the page shows in
# English that must not be left over in any other language.
PAGES: dict[str, tuple[dict[str, str], list[str]]] = {
    "/": (
        {"ha": "Binciken yau", "yo": "Àwọn àyẹ̀wò òní", "ig": "Nlele taa", "pcm": "Today inspections"},
        ["Today’s inspections", "No inspections yet today.", "Latest today"],
    ),
    "/admin/stations": (
        {"ha": "Tashoshi", "yo": "Àwọn ibùdó", "ig": "Ọdụ", "pcm": "Settings wey dey work now"},
        ["Weighbridge stations submit readings over the API", "Calibration valid until", "Add a station"],
    ),
    "/admin/stations/new": (
        {"ha": "Ƙara tasha", "yo": "Fi ibùdó kún un", "ig": "Tinye ọdụ", "pcm": "Go back to di stations"},
        ["The station's key is shown once, on the next page.", "Back to the stations"],
    ),
    "/admin/settings": (
        {
            "ha": "Saitunan da ke aiki",
            "yo": "Àwọn ètò tó wà lójú ìlò",
            "ig": "Ntọala ndị na-arụ ọrụ",
            "pcm": "Settings wey dey work now",
        },
        ["These settings decide inspections, certificates and sign-in.", "Settings in force"],
    ),
    "/statistics": (
        {"ha": "Ƙididdiga", "yo": "Ìṣirò", "ig": "Ọnụọgụgụ", "pcm": "Download di count for each day (CSV)"},
        [
            "Download the counts per day (CSV)",
            "Per station",
            "Inspections per day, newest first",
            "compliant share",
        ],
    ),
    "/admin/audit": (
        {
            "ha": "Tarihin ayyuka",
            "yo": "Àkọsílẹ̀ ìṣe",
            "ig": "Ndekọ omume",
            "pcm": "Download dis events (CSV)",
        },
        ["The record is intact.", "Download these events (CSV)", "Kind of actor"],
    ),
    "/admin/users": (
        {"ha": "Masu amfani", "yo": "Àwọn olùlò", "ig": "Ndị ojiji", "pcm": "Add user"},
        ["Add a user", "Set a new password"],
    ),
    "/admin/reminders": (
        {"ha": "Tunatarwa", "yo": "Ìránnilétí", "ig": "Ncheta", "pcm": "Na only di count"},
        ["Counts only: who subscribed is never shown.", "Waiting for confirmation", "The last 30 days"],
    ),
}

_TAG = re.compile(r"<[^>]+>")


def visible(page: str) -> str:
    """The text a reader sees (tags dropped, entities read), with runs of spaces made one."""
    return " ".join(html.unescape(_TAG.sub(" ", page)).split())


@pytest.mark.parametrize("language", LANGUAGES)
@pytest.mark.parametrize("path", list(PAGES))
def test_an_officer_page_speaks_the_chosen_language(
    admin_web: TestClient, station: Station, path: str, language: str
) -> None:
    expected, english = PAGES[path]
    assert all(sentence in visible(admin_web.get(path).text) for sentence in english)

    admin_web.cookies.set("trikecert_lang", language)
    response = admin_web.get(path)

    assert response.status_code == 200
    assert f'<html lang="{language}"' in response.text
    text = visible(response.text)
    assert expected[language] in text
    assert [sentence for sentence in english if sentence in text] == []


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_sign_in_and_code_pages_speak_the_chosen_language(
    client: TestClient, admin: User, language: str
) -> None:
    client.cookies.set("trikecert_lang", language)
    signed_out = visible(client.get("/login").text)
    assert "Sign in with the email address and password your administrator gave you." not in signed_out
    assert {
        "ha": "Adireshin imel",
        "yo": "Àdírẹ́sì ímeèlì",
        "ig": "Adreesị email",
        "pcm": "wey your admin give you",
    }[language] in signed_out
