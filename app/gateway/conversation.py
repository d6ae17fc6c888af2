"""What a feature phone says and gets back, whoever the gateway is: the USSD menu and the SMS keywords,
in the language the phone chose (USSD 4, SMS LANG; English until it chooses)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from datetime import datetime

from sqlalchemy.orm import Session

from app.config import Settings
from app.gateway.check import answer, ask, is_number, not_registered
from app.i18n.active import current_locale, ngettext, use_locale
from app.i18n.active import gettext as _
from app.i18n.locales import ENGLISH
from app.notifications import service
from app.notifications.contacts import ContactRefused, mask_phone, normalise_phone
from app.notifications.languages import (
    BY_NUMBER,
    LANGUAGE_WORDS,
    PHONE_NAMES,
    choose_language,
    parse_language,
    phone_language,
)
from app.notifications.messages import Text
from app.notifications.sms_text import USSD_SCREEN, first_fitting
from app.vehicles.service import display_registration, find_vehicle, lookup_key

# A USSD answer starts "CON " or "END ": the words after it fit the rest of one screen.
SCREEN = USSD_SCREEN - 4
# The choice of language, named in all five languages so a reader of any finds it.
LANGUAGE_LINE = "4. Language/Harshe/Ede/Asusu"
LANGUAGE_CHOICES = "\n".join(f"{number}. {PHONE_NAMES[locale]}" for number, locale in BY_NUMBER.items())
QUERY_LENGTH = 80
_CODE = re.compile(r"(?:YES\s+)?(\d{6})")


@dataclass(frozen=True)
class Screen:
    """One USSD screen: its words, and whether the session goes on (CON) or ends (END)."""

    text: str
    more: bool

    def wire(self) -> str:
        """As the gateway takes it: 'CON ...' or 'END ...'."""
        return f"{'CON' if self.more else 'END'} {first_fitting([self.text], SCREEN)}"


def menu() -> str:
    """The first USSD screen in the active language, choice 4 (the language) named in all five: a
    phone that has not chosen yet reads English, and must find its own language from there."""
    lines = [
        _("Keke check"),
        _("1. Check a keke"),
        _("2. Remind me before it expires"),
        _("3. Stop reminders"),
        LANGUAGE_LINE,
    ]
    return "\n".join(lines)


def language_chosen(locale: str) -> str:
    """The reply to a choice of language, in that language."""
    with use_locale(locale):
        return _("Replies to this phone will now be in English. Send LANG and a language to change.")


def language_refused() -> str:
    """The reply to LANG with a word that names no language: the choices."""
    return _("Unknown language. Send LANG and one of: %(choices)s.") % {
        "choices": "ENGLISH, HAUSA, YORUBA, IGBO, PIDGIN"
    }


def _remind(
    session: Session, phone: str, query: str, settings: Settings, now: datetime, key: str | None = None
) -> str | None:
    """Ask for reminders about a plate for this phone: what the phone is told (None: the code SMS is
    the answer)."""
    if lookup_key(query) is None or is_number(query):
        return _("Enter the plate, like BDG 252 QH.")
    vehicle = find_vehicle(session, query)
    if vehicle is None:
        return not_registered(display_registration(query))
    try:
        subscribed = service.subscribe(
            session,
            vehicle=vehicle,
            channel="sms",
            contact=phone,
            client=phone,
            settings=settings,
            now=now,
            dedupe_key=key,
            language=current_locale(),
        )
    except service.LimitReached:
        return _("Too many codes were sent to this phone today: try again tomorrow.")
    plate = vehicle.registration_number
    if not subscribed.confirmation_sent:
        return _("Reminders for %(plate)s already go to %(phone)s.") % {
            "plate": plate,
            "phone": mask_phone(phone),
        }
    return None


def _code_sent(phone: str, query: str) -> str:
    return _(
        "A code was sent by SMS to %(phone)s. Reply YES and the code to confirm reminders for %(plate)s."
    ) % {
        "phone": mask_phone(phone),
        "plate": query,
    }


def _stopped(count: int, phone: str) -> str:
    plates = ngettext("%(count)d plate", "%(count)d plates", count) % {"count": count}
    return _("Reminders to %(phone)s stopped (%(plates)s). Nothing more will be sent.") % {
        "phone": mask_phone(phone),
        "plates": plates,
    }


def _phone(raw: str, settings: Settings) -> str | None:
    try:
        return normalise_phone(raw[:40], settings.phone_country_code)
    except ContactRefused:
        return None


def _check(
    session: Session, phone: str, query: str, settings: Settings, now: datetime, screen: int | None
) -> str | None:
    if not service.check_allowed(session, phone, settings, now):
        return None
    return answer(session, query[: QUERY_LENGTH * 4], now, screen)


def ussd(session: Session, phone_number: str, text: str, settings: Settings, now: datetime) -> Screen:
    """The screen for a USSD session whose choices so far are `text`, joined by '*'."""
    phone = _phone(phone_number, settings)
    with use_locale(phone_language(session, phone) if phone else ENGLISH):
        screen = _ussd(session, phone, phone_number, text, settings, now)
        # Fitted here, where the language is known: a translated screen in phone spelling.
        return Screen(first_fitting([screen.text], SCREEN), screen.more)


def _ussd(
    session: Session, phone: str | None, phone_number: str, text: str, settings: Settings, now: datetime
) -> Screen:
    choices = text.split("*") if text else []
    if not choices:
        return Screen(menu(), more=True)
    first, rest = choices[0].strip(), " ".join(choices[1:]).strip()
    if first == "1":
        if not rest:
            return Screen(_("Enter the plate or certificate number"), more=True)
        reply = _check(session, phone or phone_number[:40], rest, settings, now, SCREEN)
        session.commit()
        return Screen(reply or _("Too many checks from this phone: try again in an hour."), more=False)
    if first in ("2", "3", "4") and phone is None:
        return Screen(_("Reminders go only to a phone number the gateway can name."), more=False)
    assert phone is not None or first not in ("2", "3", "4")
    if first == "2":
        if not rest:
            return Screen(_("Enter the plate to be reminded about"), more=True)
        plate = rest[:QUERY_LENGTH]
        said = _remind(session, phone or "", plate, settings, now)
        return Screen(said or _code_sent(phone or "", _plate_of(session, plate)), more=False)
    if first == "3":
        return Screen(_stopped(service.stop_phone(session, phone or "", now), phone or ""), more=False)
    if first == "4":
        chosen = BY_NUMBER.get(rest)
        if chosen is None:
            return Screen(LANGUAGE_CHOICES, more=True)
        choose_language(session, phone or "", chosen, now)
        session.commit()
        with use_locale(chosen):  # fitted in the new language's spelling
            return Screen(first_fitting([language_chosen(chosen)], SCREEN), more=False)
    return Screen(_("Choose 1, 2 or 3. %(ask)s") % {"ask": ask()}, more=False)


def _plate_of(session: Session, query: str) -> str:
    vehicle = find_vehicle(session, query)
    return vehicle.registration_number if vehicle is not None else display_registration(query)


def sms(
    session: Session, sender: str, text: str, message_id: str, settings: Settings, now: datetime
) -> str | None:
    """Act on an incoming SMS and put its reply in the outbox (one per message id: a replayed callback
    does nothing); the reply's words, or None when nothing is sent."""
    phone = _phone(sender, settings)
    key = f"sms-in:{message_id[:100]}"
    if phone is None or service.key_taken(session, key):
        return None
    words = " ".join(text[: QUERY_LENGTH * 4].split())
    keyword, _space, rest = words.partition(" ")
    keyword = keyword.upper()
    if keyword in ("LANG", "LANGUAGE") or (keyword in LANGUAGE_WORDS and not rest):
        chosen = parse_language(rest if keyword in ("LANG", "LANGUAGE") else keyword)
        if chosen is not None:
            choose_language(session, phone, chosen, now)
    with use_locale(phone_language(session, phone)):
        return _sms(session, phone, words, keyword, rest, key, settings, now)


def _sms(
    session: Session,
    phone: str,
    words: str,
    keyword: str,
    rest: str,
    key: str,
    settings: Settings,
    now: datetime,
) -> str | None:
    reply: str | None
    if keyword in ("LANG", "LANGUAGE") or (keyword in LANGUAGE_WORDS and not rest):
        chosen = parse_language(rest if keyword in ("LANG", "LANGUAGE") else keyword)
        reply = language_refused() if chosen is None else language_chosen(chosen)
    elif keyword in ("STOP", "UNSUBSCRIBE", "END", "CANCEL") and not rest:
        reply = _stopped(service.stop_phone(session, phone, now), phone)
    elif keyword == "REMIND":
        said = _remind(session, phone, rest, settings, now, key)
        if said is None:
            return _code_sent(phone, _plate_of(session, rest))  # the code itself is the answer
        reply = said
    elif _CODE.fullmatch(words.upper()):
        match = _CODE.fullmatch(words.upper())
        assert match is not None
        confirmed = service.confirm_code(session, phone, match[1], now)
        if confirmed is None:
            reply = _("That code is wrong or too old: send REMIND and the plate again.")
        else:
            vehicle = service.vehicle_of(session, confirmed)
            reply = _(
                "Reminders for %(plate)s confirmed: 30 and 7 days before its certificate expires, "
                "and a day after. Reply STOP to end."
            ) % {"plate": vehicle}
    else:
        query = rest if keyword == "CHECK" else words
        reply = _check(session, phone, query, settings, now, None) if query else ask()
    if reply is None:
        session.commit()
        return None
    service.enqueue(
        session,
        channel="sms",
        recipient=phone,
        purpose="reply",
        text=Text(None, first_fitting([reply])),
        dedupe_key=key,
        now=now,
    )
    session.commit()
    return reply
