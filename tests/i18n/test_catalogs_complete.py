"""Every marked message has a finished translation in every language, and the shipped .mo files are
the compiled .po files (so `pip install -e .` speaks Hausa with no extra step)."""

from __future__ import annotations

import io
import re
from gettext import GNUTranslations
from pathlib import Path

import pytest
from babel.messages.extract import extract_from_dir
from babel.messages.frontend import parse_mapping_cfg
from babel.messages.mofile import write_mo
from babel.messages.pofile import read_po

ROOT = Path(__file__).resolve().parents[2]
LOCALE_DIR = ROOT / "app" / "i18n" / "locale"
TRANSLATED = ("ha", "yo", "ig", "pcm")
KEYWORDS = {"_": None, "gettext": None, "ngettext": (1, 2), "pgettext": ((1, "c"), 2), "N_": None}
PLACEHOLDER = re.compile(r"%\((\w+)\)[sd]")


def _extracted() -> set[tuple[str | None, tuple[str, ...]]]:
    """(context, msgid and plural) of every message marked in app/ and templates/, as babel.cfg says."""
    with (ROOT / "babel.cfg").open() as cfg:
        method_map, options_map = parse_mapping_cfg(cfg)  # type: ignore[no-untyped-call]
    found: set[tuple[str | None, tuple[str, ...]]] = set()
    for _file, _line, message, _comments, context in extract_from_dir(
        str(ROOT), method_map, options_map, keywords=KEYWORDS
    ):
        ids = message if isinstance(message, tuple) else (message,)
        found.add((context, tuple(ids)))
    return found


def _po(locale: str):  # type: ignore[no-untyped-def]
    with (LOCALE_DIR / locale / "LC_MESSAGES" / "messages.po").open("rb") as po:
        return read_po(po, locale=locale)


@pytest.mark.parametrize("locale", TRANSLATED)
def test_every_marked_message_is_translated_with_the_same_placeholders(locale: str) -> None:
    catalog = _po(locale)
    missing, mismatched = [], []
    for context, ids in sorted(_extracted(), key=lambda item: (item[0] or "", item[1])):
        entry = catalog.get(ids[0], context=context)
        strings = (
            () if entry is None else (entry.string if isinstance(entry.string, tuple) else (entry.string,))
        )
        if entry is None or entry.fuzzy or not strings or not all(strings):
            missing.append(ids)
            continue
        wanted = set(PLACEHOLDER.findall(" ".join(ids)))
        if any(set(PLACEHOLDER.findall(text)) != wanted for text in strings):
            mismatched.append(ids)
    assert not missing, f"{locale}: {len(missing)} untranslated: {missing}"
    assert not mismatched, f"{locale}: placeholders differ: {mismatched}"


@pytest.mark.parametrize("locale", TRANSLATED)
def test_the_shipped_mo_is_the_compiled_po(locale: str) -> None:
    compiled = io.BytesIO()
    write_mo(compiled, _po(locale))
    compiled.seek(0)
    expected = GNUTranslations(compiled)
    with (LOCALE_DIR / locale / "LC_MESSAGES" / "messages.mo").open("rb") as mo:
        shipped = GNUTranslations(mo)
    assert shipped._catalog == expected._catalog  # type: ignore[attr-defined]
