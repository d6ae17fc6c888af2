"""The language a phone chose (SMS LANG, USSD 4), kept by the phone's keyed digest, never its number."""

from __future__ import annotations

from collections.abc import Iterable
from datetime import datetime

from sqlalchemy import select
from sqlalchemy.orm import Session

from app.db import utcnow
from app.i18n.locales import ENGLISH, LOCALES
from app.notifications.contacts import digest
from app.notifications.models import PhoneLanguage

LOOKUP_BATCH = 10_000  # phones per query: well within SQLite's 32,766 and PostgreSQL's 65,535 bound values
# USSD 4's numbers and the SMS words that name each language (LANG HA, HAUSA, ...).
BY_NUMBER = {"1": "en", "2": "ha", "3": "yo", "4": "ig", "5": "pcm"}
_WORDS = {
    "ENGLISH": "en",
    "HAUSA": "ha",
    "YORUBA": "yo",
    "IGBO": "ig",
    "PIDGIN": "pcm",
    "NAIJA": "pcm",
}
LANGUAGE_WORDS = frozenset(_WORDS)
# Each language named on a feature phone (ASCII, as texted), in USSD 4's order.
PHONE_NAMES = {"en": "English", "ha": "Hausa", "yo": "Yoruba", "ig": "Igbo", "pcm": "Pidgin"}


def parse_language(word: str) -> str | None:
    """The locale a texted word names ('HA', 'ha', 'HAUSA', '2' on USSD is BY_NUMBER's), else None."""
    text = word.strip().upper()
    if text in _WORDS:
        return _WORDS[text]
    lower = text.lower()
    return lower if lower in LOCALES else None


def chosen_language(session: Session, phone: str) -> str | None:
    """The language this phone chose, None when it chose none."""
    chosen = session.scalar(select(PhoneLanguage.language).where(PhoneLanguage.phone_digest == digest(phone)))
    return chosen if chosen in LOCALES else None


def chosen_languages(session: Session, phones: Iterable[str]) -> dict[str, str]:
    """The language each of these phones chose, by phone (those that chose none left out), in one
    query per `LOOKUP_BATCH` phones (a statement's bound values are limited)."""
    by_digest = {digest(phone): phone for phone in set(phones)}
    keys = sorted(by_digest)
    found: dict[str, str] = {}
    for start in range(0, len(keys), LOOKUP_BATCH):
        rows = session.execute(
            select(PhoneLanguage.phone_digest, PhoneLanguage.language).where(
                PhoneLanguage.phone_digest.in_(keys[start : start + LOOKUP_BATCH])
            )
        )
        found.update({by_digest[key]: chosen for key, chosen in rows if chosen in LOCALES})
    return found


def phone_language(session: Session, phone: str) -> str:
    """The language this phone chose, English when it chose none."""
    return chosen_language(session, phone) or ENGLISH


def choose_language(session: Session, phone: str, locale: str, now: datetime | None = None) -> None:
    """Remember the phone's language (in the caller's transaction)."""
    key = digest(phone)
    row = session.get(PhoneLanguage, key)
    if row is None:
        session.add(PhoneLanguage(phone_digest=key, language=locale, chosen_at=now or utcnow()))
    else:
        row.language = locale
        row.chosen_at = now or utcnow()
    session.flush()
