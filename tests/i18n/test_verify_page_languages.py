"""The public verify page in every state (certified, refusal, revoked, superseded, expired, not found)
speaks Hausa, Yoruba, Igbo and Pidgin: `<html lang>`, the translated headline and sentences, the plate
and the certificate number untouched. The expected words come from the catalogs (gettext under
use_locale), and one Hausa phrase per state is written out so that the test cannot pass vacuously."""

from __future__ import annotations

import html
import json
import re
from datetime import timedelta
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.certificates import answer_cache, records
from app.certificates.actors import Actor
from app.certificates.service import reissue_certificate, revoke_certificate
from app.certificates.wording import lapsed_sentence, number_headline
from app.config import get_settings
from app.i18n.active import gettext as _
from app.i18n.active import ngettext, use_locale
from app.i18n.locales import HTML_LANG
from app.trust.numbers import check_letter
from app.wording import occupancy_sentence, status_headline

LANGUAGES = ("ha", "yo", "ig", "pcm")
STATES = ("certified", "refusal", "revoked", "superseded", "expired", "not_found")
# One phrase per state as the Hausa catalog has it, written out here.
HAUSA = {
    "certified": "TAKARDAR SHAIDA MAI AIKI",
    "refusal": "BA A BA DA TAKARDAR SHAIDA BA: takardar ƙin amincewa",
    "revoked": "An janye wannan takardar shaida: ba ta tabbatar da komai.",
    "superseded": "An maye gurbin wannan takardar shaida kuma ba ta da amfani yanzu.",
    "expired": "Wannan takardar shaida ba ta da amfani yanzu: dole a sake auna abin hawa.",
    "not_found": "BA TA AIKI BA: babu takardar shaida mai wannan lamba",
}
# A front-heavy trike (every loading case complies), as tests/certificates' helpers register it.
FRONT_HEAVY: dict[str, Any] = {
    "registration_number": "KTU-417-XA",
    "make": "TVS",
    "model": "King",
    "model_year": 2021,
    "chassis_number": "MD6M14PA7L4F00123",
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
}
FRONT_HEAVY_READINGS: dict[str, Any] = {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80}
SECOND = {**FRONT_HEAVY, "registration_number": "KTU-418-XA", "chassis_number": None}
MISSING = f"TRK-2026-999999-{check_letter('2026999999')}"


def register(api: TestClient, vehicle: dict[str, Any]) -> None:
    assert api.post("/api/v1/vehicles", json=vehicle).status_code == 201


def weigh(api: TestClient, registration: str, readings: dict[str, Any]) -> int:
    response = api.post(
        "/api/v1/inspections", json={"registration_number": registration, "readings": readings}
    )
    assert response.status_code == 201, response.text
    inspection_id: int = response.json()["id"]
    return inspection_id


def certify(api: TestClient, inspection_id: int) -> dict[str, Any]:
    response = api.post(f"/api/v1/inspections/{inspection_id}/certificate")
    assert response.status_code == 201, response.text
    body: dict[str, Any] = response.json()
    return body


def _headline(page: str) -> str:
    found = re.search(r'<h1 class="status__headline" id="headline">(.*?)</h1>', page, re.S)
    assert found, page
    return html.unescape(found.group(1))


def _expected(state: str) -> tuple[str, str]:
    """The headline's translated status word and one sentence of the page, in the active language."""
    kind = "refusal" if state == "refusal" else "compliant"
    if state == "not_found":
        return number_headline("exists"), number_headline("exists")
    if state in ("certified", "refusal"):
        return status_headline(kind, "issued"), ""
    return status_headline(kind, state), lapsed_sentence(kind, state)


@pytest.fixture
def papers(api: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch) -> dict[str, Any]:
    """A paper in each state, by number: (number, plate). The expired one is its own clock's business."""
    register(api, FRONT_HEAVY)
    old = certify(api, weigh(api, FRONT_HEAVY["registration_number"], FRONT_HEAVY_READINGS))
    newer = reissue_certificate(
        session, number=old["number"], actor=Actor.of_cli(), reason="lost", settings=get_settings()
    )
    register(api, SECOND)
    revoked = certify(api, weigh(api, SECOND["registration_number"], FRONT_HEAVY_READINGS))
    revoke_certificate(session, number=revoked["number"], actor=Actor.of_cli(), reason="Plate does not match")
    register(api, STUDY_VEHICLE)
    refusal = certify(api, weigh(api, STUDY_VEHICLE["registration_number"], STUDY_READINGS))
    assert refusal["kind"] == "refusal"
    session.commit()
    api.headers.pop("Authorization")
    plate = FRONT_HEAVY["registration_number"]
    return {
        "certified": (newer.number, plate),
        "superseded": (old["number"], plate),
        "revoked": (revoked["number"], SECOND["registration_number"]),
        "refusal": (refusal["number"], STUDY_VEHICLE["registration_number"]),
        "expired": (newer.number, plate),
        "not_found": (MISSING, None),
    }


def _page(
    client: TestClient,
    session: Session,
    monkeypatch: pytest.MonkeyPatch,
    number: str,
    state: str,
    language: str,
) -> str:
    if state == "expired":
        found = records.find_certificate(session, number)
        assert found is not None
        later = found.expires_at + timedelta(seconds=1)
        for clock in (records, answer_cache):
            monkeypatch.setattr(clock, "utcnow", lambda: later)
    response = client.get(f"/verify/{number}", headers={"Accept-Language": language})
    assert response.status_code == (404 if state == "not_found" else 200), response.text
    return response.text


@pytest.mark.parametrize("state", STATES)
def test_the_verify_page_speaks_each_language_in_each_state(
    papers: dict[str, Any], api: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch, state: str
) -> None:
    number, plate = papers[state]
    english = html.unescape(_page(api, session, monkeypatch, number, state, "en"))
    with use_locale("en"):
        english_headline = _expected(state)[0]
    assert english_headline in english
    shown_plate = re.findall(r'<span id="registration">([^<]*)</span>', english)
    assert shown_plate == ([] if plate is None else [plate.replace("-", " ")]) or shown_plate == [plate]
    for language in LANGUAGES:
        page = _page(api, session, monkeypatch, number, state, language)
        text = html.unescape(page)
        assert f'<html lang="{HTML_LANG[language]}">' in page
        with use_locale(language):
            headline, sentence = _expected(state)
        assert headline != english_headline, (language, headline)
        assert headline in _headline(page), (language, _headline(page))
        assert english_headline not in text, language
        if state in ("revoked", "superseded", "expired"):
            assert sentence in text, (language, sentence)
        assert number in text  # the number as given or as issued, never rewritten
        assert re.findall(r'<span id="registration">([^<]*)</span>', text) == shown_plate
        if language == "ha":
            assert HAUSA[state] in text, state


# The end of each language's occupancy for 1 and for 2 passengers, written out here.
PLURALS = {
    "ha": ("direba da fasinja har 1", "direba da fasinja har 2"),
    "yo": ("awakọ̀ àti èrò tí kò ju 1 lọ", "awakọ̀ àti èrò tí kò ju 2 lọ"),
    "ig": ("na ndị njem ruo 1", "na ndị njem ruo 2"),
    "pcm": ("the driver and up to 1 passenger", "the driver and up to 2 passengers"),
}


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_occupancy_has_its_plural_forms_in_each_language(language: str) -> None:
    with use_locale(language):
        said = [occupancy_sentence(True, n + 1) for n in (1, 2)]
        wanted = [
            _("Certified for %(occupancy)s")
            % {
                "occupancy": ngettext(
                    "the driver and up to one passenger", "the driver and up to %(count)s passengers", n
                )
                % {"count": n}
            }
            for n in (1, 2)
        ]
    assert said == wanted
    assert said[0].endswith(PLURALS[language][0]), said
    assert said[1].endswith(PLURALS[language][1]), said
    with use_locale("en"):
        assert occupancy_sentence(True, 2) == "Certified for the driver and up to one passenger"
        assert occupancy_sentence(True, 3) == "Certified for the driver and up to 2 passengers"


def test_the_check_page_embeds_its_words_in_the_readers_language(client: TestClient) -> None:
    """The offline checker's words (the JavaScript retypes none) come with the page, in its language."""
    versions = set()
    hausa: dict[str, Any] = {}
    for language in ("en", *LANGUAGES):
        response = client.get("/check/", headers={"Accept-Language": language})
        assert response.status_code == 200
        assert "Accept-Language" in response.headers["vary"]
        found = re.search(r'<script type="application/json" id="check-words">(.*?)</script>', response.text)
        assert found
        words = json.loads(found.group(1))
        hausa = words if language == "ha" else hausa
        with use_locale(language):
            assert words["codes"]["stale"]["headline"] == _("CANNOT CONFIRM")
            assert words["codes"]["revoked"]["headline"] == status_headline("compliant", "revoked")
            assert words["occupancy"]["certificate"][3] == occupancy_sentence(True, 3)
            assert words["titles"]["refusal"] == _("Lateral Stability Refusal")
        versions.add(re.search(r'data-version="([0-9a-f]+)"', response.text).group(1))  # type: ignore[union-attr]
    assert len(versions) == 1  # one service worker version for every language
    assert hausa["codes"]["not_genuine"]["headline"] == "BA NA GASKE BA"
