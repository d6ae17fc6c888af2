"""The catalogs say "compliant" as the glossary (docs/translations.md) does, and never as a
rendering the glossary set aside."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from babel.messages.pofile import read_po

ROOT = Path(__file__).resolve().parents[2]
COLUMNS = {"ha": 1, "yo": 2, "ig": 3, "pcm": 4}
# Renderings of "compliant" used before the glossary and the pages were made to agree.
SET_ASIDE = {"ha": ["sharaɗi"], "ig": ["erube isi", "rube isi"]}
COMPLIANT = re.compile(r"\bcompl(?:iant|ies|y)\b", re.IGNORECASE)


def _glossary_row(term: str) -> list[str]:
    for line in (ROOT / "docs" / "translations.md").read_text(encoding="utf-8").splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if cells[0] == term:
            return cells
    raise AssertionError(f"no glossary row for {term!r}")


def _translations(locale: str) -> list[tuple[str, str]]:
    """(msgid, msgstr) of every message, each plural form on its own."""
    path = ROOT / "app" / "i18n" / "locale" / locale / "LC_MESSAGES" / "messages.po"
    with path.open("rb") as po:
        catalog = read_po(po, locale=locale)
    found: list[tuple[str, str]] = []
    for message in catalog:
        if not message.id:
            continue
        ids = message.id if isinstance(message.id, tuple) else (message.id,)
        strings = message.string if isinstance(message.string, tuple) else (message.string,)
        found += [(str(ids[0]), str(string)) for string in strings]
    return found


@pytest.mark.parametrize("locale", ["ha", "ig"])
def test_compliant_is_said_as_the_glossary_says_it(locale: str) -> None:
    compliant, not_compliant = (
        words.strip() for words in _glossary_row("compliant / not compliant")[COLUMNS[locale]].split(" / ")
    )
    catalog = dict(_translations(locale))
    assert catalog["Compliant"].casefold() == compliant.casefold()
    assert catalog["Not compliant"].casefold() == not_compliant.casefold()
    left = [
        (msgid, msgstr)
        for msgid, msgstr in _translations(locale)
        if any(word in msgstr for word in SET_ASIDE[locale])
    ]
    assert left == []
    glossary = (ROOT / "docs" / "translations.md").read_text(encoding="utf-8")
    assert compliant.split()[-1] in glossary[glossary.index("- **compliant**") :][:800]


def test_every_sentence_about_compliance_in_hausa_uses_the_glossary_word() -> None:
    about = [(i, s) for i, s in _translations("ha") if COMPLIANT.search(i) and "cika" in s]
    assert about, "the Hausa catalog says 'compliant' somewhere"
    assert [(i, s) for i, s in about if "cika ka'ida" not in s and "cika ba" not in s] == []
