"""An officer who reads Hausa, Yoruba, Igbo or Pidgin registers a keke and weighs it in that language:
the labels, the refusal beside a bad reading, Table 4 and the chart speak it; the API stays English."""

from __future__ import annotations

import html
import re
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from web.webtools import OFFICER_EMAIL, PASSWORD, STUDY_READINGS, enrol_with_code, post_form, sign_in

from app.accounts.service import create_user

VEHICLE = {
    "registration_number": "BDG 252 QH",
    "make": "Bajaj",
    "model": "RE",
    "model_year": "2012",
    "wheelbase_m": "2.000",
    "driver_x_m": "0.9303",
    "passenger_x_m_1": "1.6303",
    "passenger_x_m_2": "1.6303",
    "passenger_x_m_3": "1.6303",
}
FORM_URL = "/vehicles/BDG252QH/inspections/new"

# What each language shows, written out as a reader of it would check it (the catalogs' own words).
WORDS: dict[str, dict[str, Any]] = {
    "ha": {
        "register_title": "Yi wa abin hawa rajista",
        "registration_label": "Lambar rajista",
        "wheelbase_label": "Tazarar ƙafafu (m)",
        "flash": "An yi wa abin hawa BDG 252 QH rajista.",
        "new_inspection": "Sabon bincike",
        "front_legend": "Nauyi a kan ƙafar gaba (kg)",
        "left_rear_legend": "Nauyi a kan ƙafar baya ta hagu (kg)",
        "problem": "Akwai matsala",
        "error_prefix": "Kuskure:",
        "negative": "Dole nauyi a kan ƙafar gaba ya fi 0 kuma bai wuce 1500 kg ba; an samu -5",
        "not_a_number": "Shigar da nauyi a kan ƙafar baya ta hagu a matsayin lambar kilogram, kamar 108.5",
        "table_caption": "Tebur na 4: daidaiton gefe ga kowane yanayin lodi",
        "table_headings": [
            "Jimillar nauyi (kg)",
            "Ainihin LSF",
            "Ma'auni (mafi yawa)",
            "Bambanci",
            "Sakamako",
        ],
        "verdict_tag": "Bai cika ka'ida ba",
        "chart_axis": "Yanayin lodi (mutanen ciki)",
        "listed": "Ana nuna 1 zuwa 1 cikin bincike 1, sabo da farko.",
    },
    "yo": {
        "register_title": "Forúkọ ọkọ̀ sílẹ̀",
        "registration_label": "Nọ́mbà ìforúkọsílẹ̀",
        "wheelbase_label": "Àlàfo àgbá (m)",
        "flash": "A ti forúkọ ọkọ̀ BDG 252 QH sílẹ̀.",
        "new_inspection": "Àyẹ̀wò tuntun",
        "front_legend": "Ìwúwo lórí àgbá iwájú (kg)",
        "left_rear_legend": "Ìwúwo lórí àgbá ẹ̀yìn òsì (kg)",
        "problem": "Ìṣòro kan wà",
        "error_prefix": "Àṣìṣe:",
        "negative": "Ìwúwo lórí àgbá iwájú gbọ́dọ̀ ju 0 lọ kí ó má sì ju 1500 kg lọ; a rí -5",
        "not_a_number": "Tẹ ìwúwo lórí àgbá ẹ̀yìn òsì gẹ́gẹ́ bí nọ́mbà kìlógíráàmù, bí 108.5",
        "table_caption": "Tábìlì 4: ìdúróṣinṣin ẹ̀gbẹ́ fún ipò ẹrù kọ̀ọ̀kan",
        "table_headings": ["Àpapọ̀ ìwúwo (kg)", "LSF gidi", "Òṣùwọ̀n (ó pọ̀jù)", "Ìyàtọ̀", "Èsì"],
        "verdict_tag": "Kò bá òfin mu",
        "chart_axis": "Ipò ẹrù (ènìyàn inú ọkọ̀)",
        "listed": "A ń fi 1 dé 1 hàn nínú àyẹ̀wò 1, tuntun jù ní àkọ́kọ́.",
    },
    "ig": {
        "register_title": "Debanye ụgbọ aha",
        "registration_label": "Nọmba ndebanye aha",
        "wheelbase_label": "Ogologo n'etiti ụkwụ (m)",
        "flash": "Edebanyela ụgbọ BDG 252 QH aha.",
        "new_inspection": "Nyocha ọhụrụ",
        "front_legend": "Ibu dị n'ụkwụ n'ihu (kg)",
        "left_rear_legend": "Ibu dị n'ụkwụ azụ aka ekpe (kg)",
        "problem": "Enwere nsogbu",
        "error_prefix": "Njehie:",
        "negative": "Ibu dị n'ụkwụ n'ihu ga-akarịrị 0 ma ọ gaghị akarị 1500 kg; e nwetara -5",
        "not_a_number": "Tinye ibu dị n'ụkwụ azụ aka ekpe dịka ọnụọgụ kilogram, dịka 108.5",
        "table_caption": "Tebụl 4: nguzosi ike n'akụkụ maka ọnọdụ ibu ọ bụla",
        "table_headings": ["Ngụkọta ibu (kg)", "LSF n'ezie", "Ọkọlọtọ (kacha)", "Ọdịiche", "Nsonaazụ"],
        "verdict_tag": "O kwekọghị n'iwu",
        "chart_axis": "Ọnọdụ ibu (ndị nọ n'ime)",
        "listed": "A na-egosi 1 ruo 1 n'ime nyocha 1, nke kacha ọhụrụ bụ ụzọ.",
    },
    "pcm": {
        "register_title": "Register vehicle",
        "registration_label": "Plate number",
        "wheelbase_label": "Wheelbase (m)",
        "flash": "Vehicle BDG 252 QH don register.",
        "new_inspection": "New inspection",
        "front_legend": "Weight for front wheel (kg)",
        "left_rear_legend": "Weight for left back wheel (kg)",
        "problem": "Problem dey",
        "error_prefix": "Mistake:",
        "negative": "Di weight for front wheel must pass 0 and no pass 1500 kg; we get -5",
        "not_a_number": "Put di weight for left back wheel as number of kilograms, like 108.5",
        "table_caption": "Table 4: side stability for each loading case",
        "table_headings": ["Total weight (kg)", "Real LSF", "Standard (max)", "Difference", "Result"],
        "verdict_tag": "E no pass",
        "chart_axis": "Loading case (people inside)",
        "listed": "We dey show 1 reach 1 of 1 inspection, newest first.",
    },
}


@pytest.fixture
def officer_web(client: TestClient, session: Session) -> TestClient:
    """A TestClient signed in as an officer who has passed the second factor (set up at sign-in)."""
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    enrol_with_code(client)
    return client


def text(page: str) -> str:
    """The page's text as a reader sees it: tags gone, entities decoded, white space collapsed."""
    return re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", page)))


def tagged(page: str, tag: str) -> list[str]:
    """The text of every such element of the page."""
    return [text(found).strip() for found in re.findall(rf"<{tag}[^>]*>(.*?)</{tag}>", page, re.S)]


def label_of(page: str, input_id: str) -> str:
    """The text of an input's label."""
    found = re.search(rf'<label class="label[^"]*" for="{re.escape(input_id)}">(.*?)</label>', page, re.S)
    assert found, f"no label for {input_id}"
    return text(found[1]).strip()


def error_beside(page: str, input_id: str) -> str:
    """The message shown beside an input (its -error paragraph), as text."""
    found = re.search(rf'<p id="{re.escape(input_id)}-error" class="error-message">(.*?)</p>', page, re.S)
    assert found, f"no message beside {input_id}"
    return text(found[1]).strip()


@pytest.mark.parametrize("language", ["ha", "yo", "ig", "pcm"])
def test_an_officer_registers_and_weighs_a_keke_in_their_language(
    officer_web: TestClient, language: str
) -> None:
    words = WORDS[language]
    officer_web.cookies.set("trikecert_lang", language)

    form = officer_web.get("/vehicles/new")
    assert f'<html lang="{language}"' in form.text
    assert words["register_title"] in tagged(form.text, "h1")
    assert label_of(form.text, "registration_number") == words["registration_label"]
    assert label_of(form.text, "wheelbase_m") == words["wheelbase_label"]

    registered = post_form(officer_web, "/vehicles/new", "/vehicles/new", VEHICLE)
    assert registered.status_code == 303
    vehicle_page = officer_web.get(registered.headers["location"])
    assert words["flash"] in text(vehicle_page.text)

    new = officer_web.get(FORM_URL)
    assert f'<html lang="{language}"' in new.text
    assert words["new_inspection"] in tagged(new.text, "h1")
    assert words["front_legend"] in tagged(new.text, "legend")
    assert words["left_rear_legend"] in tagged(new.text, "legend")

    # A negative weight is refused by the core (the API's rule), and a word is not a number (the
    # form's): each message stands beside its box in the reader's language, and nothing is stored.
    refused = post_form(
        officer_web, FORM_URL, FORM_URL, {**STUDY_READINGS, "front_kg_1": "-5", "left_rear_kg_1": "heavy"}
    )
    assert refused.status_code == 422
    assert words["problem"] in refused.text
    assert error_beside(refused.text, "left_rear_kg_1") == f"{words['error_prefix']} {words['not_a_number']}"
    refused = post_form(officer_web, FORM_URL, FORM_URL, {**STUDY_READINGS, "front_kg_1": "-5"})
    assert refused.status_code == 422
    assert error_beside(refused.text, "front_kg_1") == f"{words['error_prefix']} {words['negative']}"

    stored = post_form(officer_web, FORM_URL, FORM_URL, STUDY_READINGS)
    assert stored.status_code == 303
    result = officer_web.get(stored.headers["location"])
    assert f'<html lang="{language}"' in result.text
    table = result.text[result.text.index('id="table-4"') : result.text.index("</table>")]
    assert tagged(table, "caption") == [words["table_caption"]]
    headings = [text(h).strip() for h in re.findall(r'<th scope="col"[^>]*>(.*?)</th>', table, re.S)]
    # The second and third headings (the loading case, the weight on the rear wheels) are the wording
    # module's, translated with it; these five are the page's own.
    assert [headings[1], *headings[3:]] == words["table_headings"]
    assert words["verdict_tag"] in text(table)
    assert "0.696" in table  # figures as they are, in every language
    assert "359.00" in table
    assert words["chart_axis"] in text(result.text)

    listed = officer_web.get("/inspections")
    assert words["listed"] in text(listed.text)


def test_the_api_answers_in_english_whatever_the_language_cookie(
    officer_web: TestClient, api: TestClient
) -> None:
    registered = post_form(officer_web, "/vehicles/new", "/vehicles/new", VEHICLE)
    assert registered.status_code == 303
    body = {
        "registration_number": "BDG252QH",
        "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 400},
    }
    api.cookies.set("trikecert_lang", "ha")
    in_hausa = api.post("/api/v1/inspections", json=body, headers={"Accept-Language": "ha"})
    api.cookies.clear()
    in_english = api.post("/api/v1/inspections", json=body)
    assert in_hausa.status_code == in_english.status_code == 422
    assert in_hausa.json() == in_english.json()
    assert in_hausa.json()["detail"] == (
        "readings.overall_kg: The three wheel readings add up to 358 kg but the overall weight is 400 kg; "
        "the difference (10.5 %) is more than the allowed 1 %. Weigh the vehicle again."
    )
