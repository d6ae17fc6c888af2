"""An officer reading the inspection page in Hausa, Yoruba, Igbo or Pidgin reads what would make the
study keke comply in that language: every remedy, its figures as they are, and the chart's caption."""

from __future__ import annotations

import html
import re

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.config import get_settings
from app.inspections.models import Inspection
from app.inspections.service import InspectionRequest, record_inspection
from app.vehicles.models import Vehicle
from web.webtools import wheel_readings

# The study's sentence at its default target and ballast position, in each language (the catalogs'
# words, glossary terms: ballast, front wheel, tyre, rear bench as on the form's radio buttons).
STUDY = {
    "ha": (
        "Kada a ɗauki fiye da direba; ko a saka ƙarin nauyi fiye da 54.64 kg 0.30 m a bayan ƙafar gaba; "
        "ko a matsar da kujerar baya gaba da 0.262 m, amma hakan zai bar abin hawa fanko bai cika ka'ida "
        "ba; ko a saka tayoyin baya waɗanda ƙarfin riƙe hanyarsu a kwana ya kai aƙalla sau 1.226 na "
        "tayoyin gaba."
    ),
    "yo": (
        "Má ṣe gbé ju awakọ̀ lọ; tàbí fi ẹrù àfikún tó ju 54.64 kg lọ sí 0.30 m lẹ́yìn àgbá iwájú; tàbí "
        "sún ìjókòó ẹ̀yìn síwájú ní 0.262 m, ṣùgbọ́n ọkọ̀ òfìfo kò ní bá òfin mu síbẹ̀; tàbí fi táyà "
        "ẹ̀yìn tí ìdìmú ọ̀nà wọn nígbà tí ọkọ̀ bá ń yí kọ̀rọ̀ pọ̀ ní ó kéré tán ní ìlọ́po 1.226 ti àwọn "
        "iwájú."
    ),
    "ig": (
        "Ebula karịa onye ọkwọ ụgbọala; ma ọ bụ tinye ibu mgbakwunye karịrị 54.64 kg 0.30 m n'azụ ụkwụ "
        "n'ihu; ma ọ bụ kwaga oche azụ n'ihu 0.262 m, mana nke a ka na-ahapụ ụgbọ efu ka o kwekọghị "
        "n'iwu; ma ọ bụ tinye taya azụ nke ike njide ha n'ebe ntụgharị dịkarịa ala ugboro 1.226 karịa "
        "nke n'ihu."
    ),
    "pcm": (
        "No carry pass di driver; or put extra weight wey pass 54.64 kg 0.30 m behind di front wheel; or "
        "move di back seat forward 0.262 m, but di empty vehicle still no go pass; or put back tyres wey "
        "hold road for corner at least 1.226 times pass di front ones."
    ),
}
# The chart's caption names the remedy applied.
APPLIED = {
    "ha": "bayan an saka ƙarin nauyi na 54.64 kg 0.30 m a bayan ƙafar gaba",
    "yo": "lẹ́yìn tí a fi ẹrù àfikún 54.64 kg sí 0.30 m lẹ́yìn àgbá iwájú",
    "ig": "mgbe etinyere ibu mgbakwunye 54.64 kg 0.30 m n'azụ ụkwụ n'ihu",
    "pcm": "after dem put 54.64 kg extra weight 0.30 m behind di front wheel",
}
# Ballast 1.5 m back, beyond two thirds of the 2 m wheelbase, cannot help.
CANNOT_HELP = {
    "ha": "Ƙarin nauyi 1.50 m a bayan ƙafar gaba ba zai taimaka ba",
    "yo": "Ẹrù àfikún 1.50 m lẹ́yìn àgbá iwájú kò lè ṣèrànwọ́",
    "ig": "Ibu mgbakwunye 1.50 m n'azụ ụkwụ n'ihu agaghị enyere aka",
    "pcm": "Extra weight 1.50 m behind di front wheel no fit help",
}
# The bench moved, the target two occupants, the ballast ahead of the wheel.
SEAT_SHIFT = {
    "ha": ("0.20 m a gaban ƙafar gaba", "bayan an matsar da kujerar baya gaba da 0.191 m"),
    "yo": ("0.20 m níwájú àgbá iwájú", "lẹ́yìn tí a sún ìjókòó ẹ̀yìn síwájú ní 0.191 m"),
    "ig": ("0.20 m n'ihu ụkwụ n'ihu", "mgbe a kwagara oche azụ n'ihu 0.191 m"),
    "pcm": ("0.20 m for front of di front wheel", "after dem move di back seat forward 0.191 m"),
}
# English the page shows in English, which must not be left in any other language.
ENGLISH = [
    "Carry no more than",
    "fit more than",
    "of ballast",
    "behind the front wheel",
    "ahead of the front wheel",
    "move the rear bench",
    "which still leaves",
    "non-compliant",
    "times as stiff in cornering",
    "cannot help",
    "after fitting",
    "after moving",
]


@pytest.fixture
def study(session: Session, study_vehicle: Vehicle) -> Inspection:
    readings = wheel_readings(108, 115, 135, 359)
    return record_inspection(
        session,
        request=InspectionRequest(registration_number="BDG252QH", readings=readings),
        rules=get_settings().rules(),
    )


def visible(page: str) -> str:
    """The text a reader sees (tags dropped, entities read), with runs of spaces made one."""
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", page)).split())


def sentence(page: str) -> str:
    found = re.search(r'<p class="panel__remedies" id="remedies-sentence">(.*?)</p>', page, re.S)
    assert found is not None
    return visible(found[1])


def remedies_section(page: str) -> str:
    return visible(page[page.index('id="remedies-section"') : page.index("</section>")])


@pytest.mark.parametrize("language", ["ha", "yo", "ig", "pcm"])
def test_the_remedies_speak_the_chosen_language(web: TestClient, study: Inspection, language: str) -> None:
    web.cookies.set("trikecert_lang", language)

    page = web.get(f"/inspections/{study.id}")
    assert page.status_code == 200
    assert f'<html lang="{language}"' in page.text
    assert sentence(page.text) == STUDY[language]
    section = remedies_section(page.text)
    assert APPLIED[language] in section
    assert [words for words in ENGLISH if words in section] == []

    moved = web.get(
        f"/inspections/{study.id}",
        params={"target_occupants": "2", "ballast_x_m": "-0.2", "remedy": "seat_shift"},
    )
    ahead, applied = SEAT_SHIFT[language]
    assert ahead in sentence(moved.text)
    assert applied in remedies_section(moved.text)
    assert [words for words in ENGLISH if words in remedies_section(moved.text)] == []

    behind = web.get(f"/inspections/{study.id}", params={"ballast_x_m": "1.5"})
    assert CANNOT_HELP[language] in sentence(behind.text)
    assert [words for words in ENGLISH if words in remedies_section(behind.text)] == []


def test_the_remedies_stay_the_same_english(web: TestClient, study: Inspection) -> None:
    page = web.get(f"/inspections/{study.id}")
    assert sentence(page.text).startswith(
        "Carry no more than the driver; or fit more than 54.64 kg of ballast 0.30 m behind the front wheel"
    )
    assert "after fitting 54.64 kg of ballast 0.30 m behind the front wheel" in remedies_section(page.text)
