"""The languages trikecert speaks, each named in its own language, and the choice among them."""

from __future__ import annotations

from typing import Final

ENGLISH: Final = "en"
# English first: it is the source and the legally binding text.
LOCALES: Final[tuple[str, ...]] = ("en", "ha", "yo", "ig", "pcm")
# Each language named as its readers write it (the switcher shows these).
NATIVE_NAMES: Final[dict[str, str]] = {
    "en": "English",
    "ha": "Hausa",
    "yo": "Yorùbá",
    "ig": "Igbo",
    "pcm": "Naijá",
}
# The English names (the officer's choice of a paper's second language, the docs).
ENGLISH_NAMES: Final[dict[str, str]] = {
    "en": "English",
    "ha": "Hausa",
    "yo": "Yoruba",
    "ig": "Igbo",
    "pcm": "Nigerian Pidgin",
}
# The BCP 47 tag each page's <html lang> carries (English as written in Nigeria and Britain).
HTML_LANG: Final[dict[str, str]] = {"en": "en-GB", "ha": "ha", "yo": "yo", "ig": "ig", "pcm": "pcm"}


def known_locale(value: str | None) -> str | None:
    """The supported locale a tag names ('ha', 'ha-NG', 'HA_ng'), or None for anything else."""
    if not value or len(value) > 35:
        return None
    primary = value.strip().replace("_", "-").split("-", 1)[0].lower()
    return primary if primary in LOCALES else None


def negotiate(accept_language: str | None) -> str:
    """The best supported locale for an Accept-Language header, by its q-values; English if none."""
    best, best_q = ENGLISH, 0.0
    for part in (accept_language or "")[:1000].split(",")[:50]:
        tag, _, params = part.partition(";")
        locale = known_locale(tag)
        if locale is None:
            continue
        q = 1.0
        params = params.strip()
        if params.startswith("q="):
            try:
                q = float(params[2:])
            except ValueError:
                continue
        if not 0.0 < q <= 1.0:
            continue
        # Strictly greater: of equal q-values the header's first one wins.
        if q > best_q:
            best, best_q = locale, q
    return best
