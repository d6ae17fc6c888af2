"""The officer pages speak the language the officer chose (cookie trikecert_lang): Hausa, Yoruba,
Igbo or Nigerian Pidgin, with none of the page's English sentences left over."""

from __future__ import annotations

import html
import re
from decimal import Decimal

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.config import get_settings
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import WheelReadings
from app.stations.models import Station
from app.vehicles.models import Vehicle
from app.vehicles.service import register_vehicle
from web.webtools import post_form

LANGUAGES = ["ha", "yo", "ig", "pcm"]

# Per page: a characteristic translation per language (the glossary's, docs/translations.md), and
# English sentences the page shows in English that must not be left over in any other language.
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


# Pages whose address names a record: the path from the fixtures' ids.
RECORD_PAGES: dict[str, tuple[str, dict[str, str], list[str]]] = {
    "new user": (
        "/admin/users/new",
        {
            "ha": "Ƙara mai amfani",
            "yo": "Fi olùlò kún un",
            "ig": "Tinye onye ojiji",
            "pcm": "Admin: e dey manage users too",
        },
        [
            "Officer: records inspections",
            "Administrator: also manages users",
            "As it should be printed on certificates, like Amina Bello",
            "Give it to the person in a safe way; they cannot see it here again.",
        ],
    ),
    "name and badge": (
        "/admin/users/{officer}/edit",
        {"ha": "Suna da baji", "yo": "Orúkọ àti báàjì", "ig": "Aha na baajị", "pcm": "Name and badge"},
        [
            "Documents already issued keep the name they were issued with.",
            "Letters, digits, spaces, '.', '/' or '-', like NSCDC/4471",
            "Badge number (optional)",
        ],
    ),
    "new password": (
        "/admin/users/{officer}/password",
        {
            "ha": "Sabuwar kalmar sirri",
            "yo": "Ọ̀rọ̀ aṣínà tuntun",
            "ig": "Okwuntughe ọhụrụ",
            "pcm": "Dem go sign di person out everywhere",
        },
        ["The person will be signed out everywhere and must sign in with the new password."],
    ),
    "station": (
        "/admin/stations/{station}",
        {"ha": "Canza maɓallin", "yo": "Pààrọ̀ kọ́kọ́rọ́ náà", "ig": "Gbanwee igodo ahụ", "pcm": "Change di key"},
        [
            "Active: its key is accepted",
            "The old key stops working at once",
            "The last day the calibration is valid",
        ],
    ),
    "assess a model": (
        "/type-assessments/new",
        {
            "ha": "Kimanta samfuri",
            "yo": "Ìṣàyẹ̀wò àwòṣe",
            "ig": "Ntụle ụdị",
            "pcm": "Type assessment dey judge",
        },
        [
            "A type assessment judges a make and model",
            "Show the vehicles",
            "Models on file",
            "Blank: every year",
        ],
    ),
}


@pytest.mark.parametrize("language", LANGUAGES)
@pytest.mark.parametrize("page", list(RECORD_PAGES))
def test_an_officer_page_of_a_record_speaks_the_chosen_language(
    admin_web: TestClient, station: Station, officer: User, page: str, language: str
) -> None:
    template, expected, english = RECORD_PAGES[page]
    path = template.format(officer=officer.id, station=station.id)
    assert all(sentence in visible(admin_web.get(path).text) for sentence in english)

    admin_web.cookies.set("trikecert_lang", language)
    response = admin_web.get(path)

    assert response.status_code == 200
    assert f'<html lang="{language}"' in response.text
    text = visible(response.text)
    assert expected[language] in text
    assert [sentence for sentence in english if sentence in text] == []


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_users_list_names_the_roles_in_the_chosen_language(
    admin_web: TestClient, officer: User, language: str
) -> None:
    admin_web.cookies.set("trikecert_lang", language)
    text = visible(admin_web.get("/admin/users").text)
    role = {"ha": "Jami'i", "yo": "Òṣìṣẹ́", "ig": "Onye ọrụ", "pcm": "Officer"}[language]
    assert role in text
    if language != "pcm":
        assert "Officer" not in text.replace("Officer:", "")


def test_a_form_error_and_a_flash_are_in_the_chosen_language(
    admin_web: TestClient, station: Station, officer: User
) -> None:
    admin_web.cookies.set("trikecert_lang", "ha")
    edit = f"/admin/stations/{station.id}"
    refused = post_form(admin_web, edit, edit, {"name": "", "capacity_kg": "0"})
    assert refused.status_code == 422
    text = visible(refused.text)
    assert "Shigar da sunan tashar, misali Agbara weighbridge" in text
    assert "Iya nauyi dole ya fi 0 kg" in text
    assert "Enter the station's name" not in text

    admin_web.cookies.set("trikecert_lang", "yo")
    saved = post_form(admin_web, edit, edit, {"location": "Ikeja"})
    assert saved.status_code == 303
    shown = visible(admin_web.get(saved.headers["location"]).text)
    assert f"A ti fi àlàyé {station.name} pamọ́." in shown
    assert "were saved" not in shown


def test_an_account_refusal_is_translated_on_the_page_and_stays_english_in_english(
    admin_web: TestClient, officer: User
) -> None:
    path = f"/admin/users/{officer.id}/password"
    assert "Use at least 10 characters" in post_form(admin_web, path, path, {"password": "short"}).text
    admin_web.cookies.set("trikecert_lang", "ig")
    refused = post_form(admin_web, path, path, {"password": "short"})
    assert refused.status_code == 422
    assert "Jiri opekata mpe mkpụrụedemede 10" in visible(refused.text)


# The settings table: each setting's name and meaning, and a value that is words, per language.
SETTINGS_WORDS: dict[str, list[str]] = {
    "ha": [
        "Nauyin mai zama a ciki",
        "Tsawon lokacin da takardar shaidar daidaiton gefe take aiki.",
        "watanni 12",
    ],
    "yo": ["Ìwúwo ẹni tó wà nínú ọkọ̀", "Bí ìwé-ẹ̀rí ìdúróṣinṣin ẹ̀gbẹ́ ṣe ń wúlò pẹ́ tó.", "oṣù 12"],
    "ig": ["Ibu onye nọ n'ime ya", "Ogologo oge asambodo nkwụsi ike n'akụkụ na-adị irè.", "ọnwa 12"],
    "pcm": [
        "Weight of person wey dey inside",
        "How long di certificate of how e stand well for side",
        "12 months",
    ],
}
# Their English, and the rest of the table's English words, which must not be left over.
SETTINGS_ENGLISH = [
    "Occupant mass",
    "How long a Lateral Stability Certificate is valid.",
    "Sum tolerance",
    "Calibration required",
    "An officer is signed out after this idle.",
    "Failed sign-ins before lock-out",
    "Second factor at sign-in",
    "every officer signs in with a code",
    "Where the remedies place front ballast",
    "Not set",
    "Yes",
    "minutes",
    "hours",
    "seconds",
    "requests",
]


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_settings_table_speaks_the_chosen_language(admin_web: TestClient, language: str) -> None:
    english = visible(admin_web.get("/admin/settings").text)
    assert all(words in english for words in [*SETTINGS_ENGLISH[:9], "12 months", "Not set (default)"])

    admin_web.cookies.set("trikecert_lang", language)
    table = admin_web.get("/admin/settings").text
    table = visible(table[table.index("<table") : table.index("</table>")])

    assert all(words in table for words in SETTINGS_WORDS[language])
    left = [words for words in SETTINGS_ENGLISH if re.search(rf"\b{re.escape(words)}\b", table)]
    assert left == ([] if language != "pcm" else [w for w in left if w in PIDGIN_AS_ENGLISH])
    # The environment's names and values stay as they are typed: the variable, the mfa mode.
    assert "TRIKECERT_" in table
    assert "optional" in table


# Words Pidgin speakers use as they are (docs/translations.md): the same in both.
PIDGIN_AS_ENGLISH = {"Yes", "minutes", "hours", "seconds", "requests"}


def _weigh_a_tadpole(session: Session) -> None:
    """A tadpole weighed today, so the statistics show the per-layout table."""
    register_vehicle(
        session,
        registration_number="TDP 101 EV",
        make="Example",
        model="E-Tadpole",
        wheelbase_m=Decimal("1.900"),
        seats=[("driver", Decimal("0.700")), ("passenger", Decimal("1.350"))],
        layout="tadpole",
    )
    readings = WheelReadings(
        left_front_kg=(Decimal("120"),), right_front_kg=(Decimal("118"),), rear_kg=(Decimal("140"),)
    )
    record_inspection(
        session,
        request=InspectionRequest(registration_number="TDP 101 EV", readings=readings),
        rules=get_settings().rules(),
    )


STATISTICS_WORDS: dict[str, tuple[str, str]] = {
    "ha": ("Tadpole (ƙafafun gaba biyu da ƙafar baya ɗaya): iyaka 1/3", "Ranar 'zuwa' dole ta zama"),
    "yo": ("Tadpole (àgbá iwájú méjì àti àgbá ẹ̀yìn kan): ààlà 1/3", "Ọjọ́ 'dé' gbọ́dọ̀ jẹ́"),
    "ig": ("Tadpole (ụkwụ n'ihu abụọ na otu ụkwụ azụ): oke 1/3", "Ụbọchị 'ruo' ga-abụ"),
    "pcm": ("Tadpole (two front wheels and one back wheel): limit 1/3", "Di 'to' date must be"),
}


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_statistics_name_the_layouts_and_the_fields_in_the_chosen_language(
    admin_web: TestClient, session: Session, language: str
) -> None:
    _weigh_a_tadpole(session)
    english = visible(admin_web.get("/statistics").text)
    assert "Tadpole (two front wheels and one rear wheel): limit 1/3 (0.333)" in english

    admin_web.cookies.set("trikecert_lang", language)
    layout, refusal = STATISTICS_WORDS[language]
    text = visible(admin_web.get("/statistics").text)
    assert layout in text
    assert "two front wheels and one rear wheel" not in text
    refused = admin_web.get("/statistics", params={"from": "2026-12-01", "to": "2026-11-01"})
    assert refused.status_code == 422
    assert refusal in visible(refused.text)
    assert "'from'" not in visible(refused.text) or language == "pcm"


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_vehicle_page_words_a_gap_in_the_chosen_language(
    admin_web: TestClient, study_vehicle: Vehicle, language: str
) -> None:
    assert "Chassis number Not recorded" in visible(admin_web.get("/vehicles/BDG252QH").text)

    admin_web.cookies.set("trikecert_lang", language)
    text = visible(admin_web.get("/vehicles/BDG252QH").text)
    gap = {"ha": "Ba a rubuta ba", "yo": "A kò kọ ọ́ sílẹ̀", "ig": "Edebeghị ya", "pcm": "Dem no record am"}
    assert gap[language] in text
    assert "Not recorded" not in text


SERVICE_NAMES = {
    "ha": "Takardar shaidar daidaiton Keke",
    "yo": "Ìwé-ẹ̀rí ìdúróṣinṣin Keke",
    "ig": "Asambodo nkwụsi ike Keke",
    "pcm": "Certificate for how Keke stand well",
}


@pytest.mark.parametrize("language", LANGUAGES)
@pytest.mark.parametrize("path", ["/", "/verify", "/check/"])
def test_the_header_names_the_service_in_the_chosen_language(
    admin_web: TestClient, path: str, language: str
) -> None:
    assert "Keke stability certification" in admin_web.get(path).text

    admin_web.cookies.set("trikecert_lang", language)
    page = admin_web.get(path).text
    header = re.search(r'class="header__service">(.*?)</', page, re.S)
    assert header is not None
    assert html.unescape(header[1]).strip() == SERVICE_NAMES[language]
    title = re.search(r"<title>(.*?)</title>", page, re.S)
    assert title is not None
    assert html.unescape(title[1]).endswith(f" – {SERVICE_NAMES[language]}")
    assert "Keke stability certification" not in page
