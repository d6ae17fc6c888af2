"""A paper in two languages (issue 24, item 4): English first and binding, the officer's second language
under each English line, the same signed claims whatever the language, every letter in the font.

Expected translations are read from the catalogs (gettext under use_locale), never written here, so the
tests hold as the catalogs fill in. With TRIKECERT_SCREENSHOTS=1 a certificate and a refusal in each
language are rendered to docs/screenshots/i18n/ (certificate-LL.png, refusal-LL.png; a second page as
...-LL-2.png):

    TRIKECERT_SCREENSHOTS=1 .venv/bin/pytest -p no:cacheprovider \
        tests/certificates/test_bilingual_papers.py -k screenshots
"""

from __future__ import annotations

import gettext as stdlib_gettext
import io
import os
import re
import shutil
import subprocess
import unicodedata
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import test_pdf_geometry as geometry
from babel.messages.extract import extract_from_file
from babel.messages.pofile import read_po
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, register, weigh
from fastapi.testclient import TestClient
from fontTools import ttLib
from pydantic import ValidationError
from sqlalchemy import select
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS
from test_pdf_geometry import ILLUSTRATIVE_VEHICLE, Rendered, assert_holds, pdftotext
from web.webtools import OFFICER_EMAIL, PASSWORD, hidden, sign_in

import app.certificates.service as service
import app.i18n.active as active
from app.accounts.service import create_user
from app.audit.models import AuditEvent
from app.certificates.actors import Actor
from app.certificates.models import Certificate
from app.certificates.pdf import (
    CertificateDocument,
    binding_note,
    occupancy_words,
    reading_words,
    render_with_layout,
    title,
    verdict_words,
)
from app.certificates.service import revoke_certificate
from app.certificates.stamp import status_word
from app.config import Settings, get_settings, settings_problems
from app.db import utcnow
from app.documents import fonts
from app.documents.layout import Layout
from app.i18n.active import gettext as _
from app.i18n.active import use_locale
from app.i18n.catalogs import LOCALE_DIR
from app.wording import case_name, document_headline

REPO = Path(__file__).resolve().parents[2]
SCREENSHOTS = REPO / "docs" / "screenshots" / "i18n"
LANGUAGES = ("ha", "yo", "ig", "pcm")
ISSUE = "/api/v1/inspections/{}/certificate"
# Every letter the four languages need, precomposed and as base + combining mark (issue 24).
LETTERS = "ẹọṣɓɗƙƴụịṅẸỌṢƁƊƘƳỤỊṄàáèéìíòóùúǹńÀÁÈÉÌÍÒÓÙÚǸŃ" + "ọ́ẹ̀ọ̀ẹ́ṣ̀ị́ụ̀n̄" + "\u0300\u0301\u0304\u0323"
# The modules whose words are printed on the paper.
PDF_MODULES = (
    "app/certificates/pdf.py",
    "app/certificates/stamp.py",
    "app/documents/layout.py",
    "app/documents/chart.py",
    "app/dynamics/pdf.py",
    "app/wording.py",
    "app/certificates/wording.py",
    "app/web/formatting.py",
)
KEYWORDS = {"_": None, "gettext": None, "ngettext": (1, 2), "pgettext": ((1, "c"), 2), "N_": None}


def nfc(text: str) -> str:
    """The text in Unicode's composed form, as the paper is compared."""
    return unicodedata.normalize("NFC", text)


def squeezed(text: str) -> str:
    """The text without whitespace, composed: a wrapped block reads back whole once the breaks are gone."""
    return re.sub(r"\s+", "", nfc(text))


def both(say: Callable[[], str], language: str) -> tuple[str, str]:
    """`say()` in English and in `language`, as the catalogs have it."""
    with use_locale("en"):
        english = say()
    with use_locale(language):
        return english, nfc(say())


@pytest.fixture
def layouts(monkeypatch: pytest.MonkeyPatch) -> list[tuple[bytes, Layout, CertificateDocument]]:
    """Record every document the service renders, with its bytes and layout."""
    seen: list[tuple[bytes, Layout, CertificateDocument]] = []

    def spy(document: CertificateDocument) -> bytes:
        pdf, layout = render_with_layout(document)
        seen.append((pdf, layout, document))
        return pdf

    monkeypatch.setattr(service, "render_pdf", spy)
    return seen


def issue(
    api: TestClient, inspection_id: int, body: dict[str, Any] | None = None, expected: int = 201
) -> Any:
    """Issue through the station API, `body`'s choice sent as its query; the JSON answer."""
    response = api.post(ISSUE.format(inspection_id), params=body or {})
    assert response.status_code == expected, response.text
    return response.json()


def paper(
    api: TestClient, layouts: list[Any], kind: str, language: str | None
) -> tuple[Rendered, CertificateDocument]:
    """A certificate (front-heavy trike) or a refusal (the study's) issued in English and `language`."""
    if kind == "certificate":
        register(api, FRONT_HEAVY)
        inspection_id = weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS)
    else:
        register(api)
        inspection_id = weigh(api)
    body = issue(api, inspection_id, {"second_language": language} if language else None)
    response = api.get(body["pdf_url"])
    assert response.status_code == 200
    pdf, layout, document = layouts[-1]
    assert response.content == pdf
    return Rendered(body, pdf, layout), document


def stored(session: Session, number: str) -> Certificate:
    """The certificate row, read afresh."""
    session.expire_all()
    return session.scalars(select(Certificate).where(Certificate.number == number)).one()


# --- choosing the language ----------------------------------------------------------------------


def test_a_bad_setting_is_refused_at_start_naming_the_variable() -> None:
    with pytest.raises(ValidationError) as refused:
        Settings(paper_second_language="fr")
    [line] = settings_problems(refused.value)
    assert line.startswith("TRIKECERT_PAPER_SECOND_LANGUAGE: 'fr' is not a paper language")
    assert Settings(paper_second_language="").paper_second_language == ""
    assert Settings(paper_second_language="en").paper_second_language == ""
    assert Settings(paper_second_language="YO").paper_second_language == "yo"


def test_the_api_stores_the_choice_with_the_record_and_its_audit_event(
    api: TestClient, session: Session, layouts: list[Any]
) -> None:
    register(api)
    inspection_id = weigh(api)
    bad = api.post(ISSUE.format(inspection_id), params={"second_language": "fr"})
    assert bad.status_code == 422
    assert bad.json()["errors"][0]["field"] == "second_language"
    assert not layouts  # nothing issued
    body = issue(api, inspection_id, {"second_language": "ha"})
    assert stored(session, body["number"]).second_language == "ha"
    assert layouts[-1][2].second_language == "ha"
    event = session.scalars(
        select(AuditEvent).where(
            AuditEvent.action == "refusal.issued", AuditEvent.target_id == body["number"]
        )
    ).one()
    assert '"second_language":"ha"' in event.details.replace(" ", "")
    # Asked again, the inspection's paper stays as issued, whatever language is asked for now.
    again = issue(api, inspection_id, {"second_language": "yo"}, expected=200)
    assert again["number"] == body["number"]
    assert stored(session, body["number"]).second_language == "ha"


def test_without_a_choice_the_setting_decides_and_en_asks_for_english_only(
    api: TestClient, session: Session, layouts: list[Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TRIKECERT_PAPER_SECOND_LANGUAGE", "ig")
    get_settings.cache_clear()
    try:
        register(api)
        by_setting = issue(api, weigh(api))
        assert stored(session, by_setting["number"]).second_language == "ig"
        register(api, FRONT_HEAVY)
        english = issue(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS), {"second_language": "en"})
        assert stored(session, english["number"]).second_language is None
    finally:
        monkeypatch.delenv("TRIKECERT_PAPER_SECOND_LANGUAGE")
        get_settings.cache_clear()
    register(api, {**FRONT_HEAVY, "registration_number": "KTU-418-XA"})
    default = issue(api, weigh(api, "KTU-418-XA", FRONT_HEAVY_READINGS))
    assert stored(session, default["number"]).second_language is None


def test_the_officer_picks_the_second_language_on_the_issue_form(
    api: TestClient, session: Session, layouts: list[Any]
) -> None:
    register(api)
    inspection_id = weigh(api)
    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    page = api.get(f"/inspections/{inspection_id}")
    assert '<select class="select" id="second_language" name="second_language">' in page.text
    assert '<option value="en" selected>English only</option>' in page.text
    assert '<option value="yo">English and Yoruba (Yorùbá)</option>' in page.text
    token = hidden(page.text)
    issued = api.post(
        f"/inspections/{inspection_id}/certificate",
        data={"csrf_token": token, "second_language": "yo"},
        follow_redirects=False,
    )
    assert issued.status_code == 303
    number = issued.headers["location"].rsplit("/", 1)[1]
    assert stored(session, number).second_language == "yo"
    # Once issued, the form only shows the paper: there is no language left to choose.
    assert 'name="second_language"' not in api.get(f"/inspections/{inspection_id}").text


def test_the_signed_claims_are_the_same_in_every_language(
    api: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The same facts issued at the same moment sign the same payload, English only or bilingual."""
    register(api)
    inspection_id = weigh(api)
    seen: list[CertificateDocument] = []

    class Stop(Exception):
        pass

    def stop(document: CertificateDocument) -> bytes:
        seen.append(document)
        raise Stop

    monkeypatch.setattr(service, "render_pdf", stop)
    settings = get_settings()
    now = utcnow()

    for language in (None, "en", *LANGUAGES):
        with pytest.raises(Stop):
            service.issue_certificate(
                session,
                inspection_id=inspection_id,
                actor=Actor.of_cli(),
                settings=settings,
                now=now,
                second_language=language,
            )
        session.rollback()  # the number goes back: the next language is signed under the same one
    assert [d.second_language for d in seen] == [None, None, *LANGUAGES]
    assert len({d.number for d in seen}) == 1
    assert len({d.qr_url for d in seen}) == 1  # the signed payload (CWT), byte for byte


# --- the bilingual paper ------------------------------------------------------------------------


def pairs(document: CertificateDocument, language: str) -> list[tuple[str, str]]:
    """The paper's full-width blocks, each in English and in `language`, in the paper's order."""
    facts = document.facts
    kind = document.kind
    found = [
        both(lambda: document_headline(kind, facts.max_compliant_occupants), language),
        both(lambda: occupancy_words(facts) if kind != "compliant" else verdict_words(facts), language),
        both(lambda: title(kind), language),
        both(lambda: _("Certificate number") if kind == "compliant" else _("Refusal number"), language),
        both(binding_note, language),
        both(lambda: _("Averaged readings"), language),
        both(lambda: _("Loading cases (Table 4 of the study)"), language),
        both(lambda: _("LSF per loading case against the limit %(limit)s") % {"limit": "2/3"}, language),
    ]
    if kind != "compliant":
        found.insert(
            6,
            both(
                lambda: (
                    _("%(verdict)s Reasons for refusal (cases that fail and by how much):")
                    % {"verdict": verdict_words(facts)}
                ),
                language,
            ),
        )
    return found


def labels(language: str) -> list[tuple[str, str]]:
    """The particulars' labels in English and in `language`."""
    words = ("Vehicle", "Registration", "Make", "Model", "Year", "Chassis number", "Inspection", "Station")
    return [both(lambda w=w: _(w), language) for w in words]  # type: ignore[misc]


@pytest.mark.parametrize("kind", ["certificate", "refusal"])
@pytest.mark.parametrize("language", LANGUAGES)
def test_the_bilingual_paper_reads_back_each_english_line_then_its_translation(
    api: TestClient, layouts: list[Any], kind: str, language: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    rendered, document = paper(api, layouts, kind, language)
    allow_translated_chart_words(monkeypatch, language)
    assert_holds(rendered)
    assert rendered.layout.printable.missing == set()
    text = nfc(pdftotext(pdf=rendered.pdf))
    assert "\ufffd" not in text
    flat = squeezed(text)
    position = 0
    for english, translated in pairs(document, language):
        # The English, then at once its translation (unless the catalog words it the same).
        block = squeezed(english) + ("" if translated == english else squeezed(translated))
        found = flat.find(block, position)
        assert found >= 0, (english, translated)
        position = found + len(block)
    # The readings stand in two columns, which pdftotext reads row by row: each English reading,
    # then (after its neighbour's perhaps) its translation.
    for reading in document.facts.readings:
        english, translated = both(lambda r=reading: reading_words(r), language)  # type: ignore[misc]
        assert 0 <= flat.find(squeezed(english)) < flat.find(squeezed(translated)), (english, translated)
    lines = {line.strip() for line in text.splitlines()}
    for english, translated in labels(language):
        assert english in lines
        assert translated in lines
    # Every case of Table 4 named in both languages, the English first.
    for case in document.facts.cases:
        english, translated = both(lambda c=case: case_name(c.occupants), language)  # type: ignore[misc]
        assert squeezed(english) in flat
        assert squeezed(translated) in flat
    assert binding_note() in lines
    assert both(binding_note, language)[1] in lines


def test_an_english_only_paper_says_nothing_of_languages(api: TestClient, layouts: list[Any]) -> None:
    rendered, document = paper(api, layouts, "refusal", None)
    assert document.second_language is None
    text = pdftotext(pdf=rendered.pdf)
    assert "legally binding" not in text
    assert "Page 1 of 1" in text


@pytest.mark.parametrize("language", LANGUAGES)
def test_the_estimates_section_is_bilingual_and_overlaps_nothing(
    api: TestClient, layouts: list[Any], language: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    register(api, ILLUSTRATIVE_VEHICLE)
    weighing = {
        "registration_number": "BDG 252 QH",
        "readings": STUDY_READINGS,
        "cg_lift": {"lift_height_m": 0.4, "front_kg": 94.8},
    }
    inspection = api.post("/api/v1/inspections", json=weighing)
    assert inspection.status_code == 201, inspection.text
    body = issue(api, inspection.json()["id"], {"second_language": language})
    pdf, layout, _document = layouts[-1]
    allow_translated_chart_words(monkeypatch, language)
    assert_holds(Rendered(body, pdf, layout))
    flat = squeezed(pdftotext(pdf=pdf))
    english, translated = both(
        lambda: _("Beyond the static test (estimates, not part of the verdict)"), language
    )
    assert squeezed(english + translated) in flat


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_revoked_bilingual_paper_is_stamped_in_its_two_languages(
    api: TestClient, session: Session, layouts: list[Any], language: str
) -> None:
    rendered, document = paper(api, layouts, "refusal", language)
    revoke_certificate(session, number=document.number, actor=Actor.of_cli(), reason="Wrong wheel readings")
    stamped = api.get(f"/api/v1/certificates/{document.number}/pdf")
    assert stamped.status_code == 200
    assert stamped.content.startswith(rendered.pdf)  # the stored original, untouched
    words, sizes = geometry.words_of(stamped.content)
    for word in words:
        width, _height = sizes[word.page - 1]
        assert 5 * geometry.MM <= word.x0 < word.x1 <= width - 5 * geometry.MM, word
    with use_locale(language):
        translated = nfc(status_word("revoked"))
    letters = squeezed(pdftotext(pdf=stamped.content))
    assert "REVOKEDon" in letters
    # The diagonal words read back letter by letter: every letter of the translation is there, per page.
    new = nfc(pdftotext(pdf=stamped.content)).split("\f")[:-1]  # pdftotext ends each page with \f
    old = nfc(pdftotext(pdf=rendered.pdf)).split("\f")[:-1]
    assert len(new) == len(old) >= 1
    for page_new, page_old in zip(new, old, strict=True):
        added = squeezed(page_new)
        for letter in set(squeezed(translated)):
            wanted = squeezed(page_old).count(letter) + squeezed(translated).count(letter)
            assert added.count(letter) >= wanted, letter


# --- the layout under long translations ---------------------------------------------------------

LONG = "Ẹ̀ṣọ́ ɓɗƙƴ ụịṅ ǹńọ́ẹ̀ "  # a pseudo-language's filler: every hard letter, a space to break at


class Lengthened(stdlib_gettext.NullTranslations):
    """A pseudo-language: every message 40 % longer, its placeholders kept, in letters the font must draw."""

    @staticmethod
    def longer(message: str) -> str:
        extra = max(1, round(len(message) * 0.4))
        return nfc(message + " " + (LONG * (extra // len(LONG) + 1))[:extra].strip())

    def gettext(self, message: str) -> str:
        return self.longer(message)

    def ngettext(self, singular: str, plural: str, n: int) -> str:
        return self.longer(singular if n == 1 else plural)

    def pgettext(self, context: str, message: str) -> str:
        return self.longer(message)


def catalogs_of_active() -> Callable[[str], stdlib_gettext.NullTranslations]:
    """The catalogs gettext reads (app.i18n.active's own reference, which a test replaces)."""
    found: Callable[[str], stdlib_gettext.NullTranslations] = vars(active)["translations"]
    return found


def allow_translated_chart_words(monkeypatch: pytest.MonkeyPatch, language: str) -> None:
    """Let the chart's and the map's translated words stand in their regions, as their English does."""
    words: set[str] = set()
    with use_locale(language):
        words.update((_("Shaded: unstable (LSF at or above %(limit)s)") % {"limit": "2/3"}).split())
        words.update(_("Loading case (occupants)").split())
    extra = "|".join(re.escape(word) for word in sorted(words))
    widened = {
        kind: re.compile(f"{pattern.pattern}|^({extra})$") if extra else pattern
        for kind, pattern in geometry.REGION_WORDS.items()
    }
    monkeypatch.setattr(geometry, "REGION_WORDS", widened)


@pytest.mark.parametrize("kind", ["certificate", "refusal"])
def test_translations_longer_by_two_fifths_still_fit_on_a4(
    api: TestClient, layouts: list[Any], monkeypatch: pytest.MonkeyPatch, kind: str
) -> None:
    real = catalogs_of_active()

    def pseudo(locale: str) -> stdlib_gettext.NullTranslations:
        return Lengthened() if locale == "ha" else real(locale)

    monkeypatch.setattr(active, "translations", pseudo)
    allow_translated_chart_words(monkeypatch, "ha")
    rendered, _document = paper(api, layouts, kind, "ha")
    words = assert_holds(rendered)
    assert rendered.layout.printable.missing == set()
    text = nfc(pdftotext(pdf=rendered.pdf))
    assert "\ufffd" not in text
    flat = squeezed(text)
    english, translated = both(binding_note, "ha")
    assert len(translated) > len(english) * 1.3
    assert squeezed(english + translated) in flat
    assert max(word.page for word in words) <= 3


def test_the_extreme_certificate_in_a_long_pseudo_language_overlaps_nothing(
    extreme_api: TestClient, layouts: list[Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    real = catalogs_of_active()
    monkeypatch.setattr(
        active, "translations", lambda locale: Lengthened() if locale == "ha" else real(locale)
    )
    allow_translated_chart_words(monkeypatch, "ha")
    register(extreme_api, geometry.EXTREME_VEHICLE)
    inspection = extreme_api.post("/api/v1/inspections", json=geometry.extreme_inspection())
    assert inspection.status_code == 201, inspection.text
    body = issue(extreme_api, inspection.json()["id"], {"second_language": "ha"})
    pdf, layout, _document = layouts[-1]
    assert_holds(Rendered(body, pdf, layout))


extreme_api = geometry.extreme_api


# --- the font -----------------------------------------------------------------------------------


def pdf_msgids() -> set[str]:
    """Every message id of the modules whose words the paper prints."""
    found: set[str] = set()
    for module in PDF_MODULES:
        for _lineno, message, _comments, _context in extract_from_file(
            "python", REPO / module, keywords=KEYWORDS
        ):
            found.update([message] if isinstance(message, str) else [m for m in message if m])
    return found


def test_the_embedded_font_has_every_letter_of_every_translation_the_paper_prints() -> None:
    wanted = pdf_msgids()
    assert "The English text is the legally binding one." in wanted
    characters = set(LETTERS)
    for language in LANGUAGES:
        with open(LOCALE_DIR / language / "LC_MESSAGES" / "messages.po", "rb") as po:
            catalog = read_po(po, locale=language)
        for message in catalog:
            ids = message.id if isinstance(message.id, tuple) else (message.id,)
            if not message.id or not any(i in wanted for i in ids):
                continue
            strings = message.string if isinstance(message.string, tuple) else (message.string,)
            for string in strings:
                if not isinstance(string, str):
                    continue
                characters.update(nfc(string))
                characters.update(unicodedata.normalize("NFD", string))
    for style in ("", "B"):
        font = ttLib.TTFont(io.BytesIO(fonts._faces()[style].embed))
        cmap = font.getBestCmap()
        missing = sorted(c for c in characters if c.isprintable() and ord(c) not in cmap and c != " ")
        assert not missing, [f"U+{ord(c):04X} {unicodedata.name(c, '?')}" for c in missing]


# --- screenshots --------------------------------------------------------------------------------


@pytest.mark.skipif(
    not os.environ.get("TRIKECERT_SCREENSHOTS"), reason="set TRIKECERT_SCREENSHOTS=1 to render"
)
@pytest.mark.parametrize("kind", ["certificate", "refusal"])
@pytest.mark.parametrize("language", LANGUAGES)
def test_screenshots_of_the_bilingual_papers(
    api: TestClient, layouts: list[Any], kind: str, language: str
) -> None:
    rendered, _document = paper(api, layouts, kind, language)
    binary = shutil.which("pdftoppm")
    assert binary, "pdftoppm (poppler-utils) renders the screenshots"
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    pages = pdftotext(pdf=rendered.pdf).count("\f")
    for page in range(1, pages + 1):
        name = f"{kind}-{language}" + ("" if page == 1 else f"-{page}")
        subprocess.run(
            [
                binary,
                "-r",
                "100",
                "-png",
                "-singlefile",
                "-f",
                str(page),
                "-l",
                str(page),
                "-",
                str(SCREENSHOTS / name),
            ],
            input=rendered.pdf,
            check=True,
        )


@pytest.mark.parametrize("language", LANGUAGES)
def test_a_revoked_bilingual_papers_band_warns_in_its_second_language_on_every_page(
    api: TestClient, session: Session, layouts: list[Any], language: str
) -> None:
    _rendered, document = paper(api, layouts, "refusal", language)
    revoke_certificate(session, number=document.number, actor=Actor.of_cli(), reason="Wrong wheel readings")
    stamped = api.get(f"/api/v1/certificates/{document.number}/pdf")
    assert stamped.status_code == 200
    english, warning = both(lambda: _("Not in force: do not rely on this paper."), language)
    pages = nfc(pdftotext(pdf=stamped.content)).split("\f")[:-1]
    assert len(pages) >= 1
    for page in pages:
        assert squeezed(english) in squeezed(page)  # the top band's English detail
        assert squeezed(warning) in squeezed(page)  # and the foot band's translation
    # The foot band stands below the page line and inside the stamp's frame (4 mm from the edge).
    words, sizes = geometry.words_of(stamped.content)
    for number in range(1, len(pages) + 1):
        _width, height = sizes[number - 1]
        foot = [w for w in words if w.page == number and w.y0 >= height - 10 * geometry.MM]
        assert foot, f"no band at the foot of page {number}"
        for word in foot:
            assert word.y1 <= height - 4 * geometry.MM, word
