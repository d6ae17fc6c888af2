"""How long a text is as one SMS: 160 GSM-7 characters (the extension's count twice), 70 in UCS-2."""

from __future__ import annotations

import unicodedata
from collections.abc import Iterable

from app.i18n.active import current_locale
from app.i18n.locales import ENGLISH

GSM7_SMS = 160
UCS2_SMS = 70
USSD_SCREEN = 182

# The GSM 03.38 default alphabet and, counted as two, its extension table.
_BASIC = frozenset(
    "@£$¥èéùìòÇ\nØø\rÅåΔ_ΦΓΛΩΠΨΣΘΞÆæßÉ !\"#¤%&'()*+,-./0123456789:;<=>?"
    "¡ABCDEFGHIJKLMNOPQRSTUVWXYZÄÖÑÜ§¿abcdefghijklmnopqrstuvwxyzäöñüà"
)
_EXTENSION = frozenset("^{}\\[~]|€\f")


def is_gsm7(text: str) -> bool:
    """True when every character is in the GSM-7 alphabet or its extension."""
    return all(char in _BASIC or char in _EXTENSION for char in text)


def sms_units(text: str) -> int:
    """The text's length as a single SMS counts it: septets in GSM-7, UTF-16 units otherwise."""
    if is_gsm7(text):
        return sum(2 if char in _EXTENSION else 1 for char in text)
    return len(text.encode("utf-16-le")) // 2


def sms_limit(text: str) -> int:
    """160 for a GSM-7 text, 70 for one that needs Unicode."""
    return GSM7_SMS if is_gsm7(text) else UCS2_SMS


def fits_sms(text: str) -> bool:
    """True when the text goes as one SMS."""
    return sms_units(text) <= sms_limit(text)


# Hausa's hooked letters as Hausa is texted (docs/translations.md, "SMS"); marks are dropped by NFD.
_HOOKED = str.maketrans("ɓɗƙƴƁƊƘƳ", "bdkyBDKY")


def phone_spelling(text: str) -> str:
    """The text as the language is texted on a feature phone: Hausa ɓ ɗ ƙ ƴ as b d k y, and Yoruba's and
    Igbo's dots and tone marks dropped (ẹ̀ → e, ụ → u), so a reply goes in GSM-7; pages keep the letters."""
    decomposed = unicodedata.normalize("NFD", text.translate(_HOOKED))
    return unicodedata.normalize("NFC", "".join(c for c in decomposed if not unicodedata.combining(c)))


def first_fitting(candidates: Iterable[str], screen: int | None = None) -> str:
    """The first candidate that fits one SMS (or a USSD screen of `screen` characters); the last one
    cut to fit when none does, so nothing sent is ever longer. Outside English, in phone spelling."""
    if current_locale() != ENGLISH:
        candidates = map(phone_spelling, candidates)
    last = ""
    for text in candidates:
        last = text
        if (len(text) <= screen) if screen is not None else fits_sms(text):
            return text
    if screen is not None:
        return last if len(last) <= screen else last[: screen - 3] + "..."
    while last and not fits_sms(last):
        last = last[: min(len(last) - 4, sms_limit(last) - 3)].rstrip() + "..."
    return last
