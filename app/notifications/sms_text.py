"""How long a text is as one SMS: 160 GSM-7 characters (the extension's count twice), 70 in UCS-2."""

from __future__ import annotations

from collections.abc import Iterable

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


def first_fitting(candidates: Iterable[str], screen: int | None = None) -> str:
    """The first candidate that fits one SMS (or a USSD screen of `screen` characters); the last one
    cut to fit when none does, so nothing sent is ever longer."""
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
