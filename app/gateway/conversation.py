"""What a feature phone says and gets back, whoever the gateway is: the USSD menu and the SMS keywords."""

from __future__ import annotations

import re
from dataclasses import dataclass
from datetime import datetime

from sqlalchemy.orm import Session

from app.config import Settings
from app.gateway.check import ASK, answer, is_number, not_registered
from app.notifications import service
from app.notifications.contacts import ContactRefused, mask_phone, normalise_phone
from app.notifications.messages import Text
from app.notifications.sms_text import USSD_SCREEN, first_fitting
from app.vehicles.service import display_registration, find_vehicle, lookup_key

# A USSD answer starts "CON " or "END ": the words after it fit the rest of one screen.
SCREEN = USSD_SCREEN - 4
MENU = "Keke check\n1. Check a keke\n2. Remind me before it expires\n3. Stop reminders"
ASK_CHECK = "Enter the plate or certificate number"
ASK_REMIND = "Enter the plate to be reminded about"
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


def _remind(
    session: Session, phone: str, query: str, settings: Settings, now: datetime, key: str | None = None
) -> str:
    """Ask for reminders about a plate for this phone: what the phone is told."""
    if lookup_key(query) is None or is_number(query):
        return "Enter the plate, like BDG 252 QH."
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
        )
    except service.LimitReached:
        return "Too many codes were sent to this phone today: try again tomorrow."
    plate = vehicle.registration_number
    if not subscribed.confirmation_sent:
        return f"Reminders for {plate} already go to {mask_phone(phone)}."
    return (
        f"A code was sent by SMS to {mask_phone(phone)}. "
        f"Reply YES and the code to confirm reminders for {plate}."
    )


def _stopped(count: int, phone: str) -> str:
    plates = "1 plate" if count == 1 else f"{count} plates"
    return f"Reminders to {mask_phone(phone)} stopped ({plates}). Nothing more will be sent."


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
    choices = text.split("*") if text else []
    phone = _phone(phone_number, settings)
    if not choices:
        return Screen(MENU, more=True)
    first, rest = choices[0].strip(), " ".join(choices[1:]).strip()
    if first == "1":
        if not rest:
            return Screen(ASK_CHECK, more=True)
        reply = _check(session, phone or phone_number[:40], rest, settings, now, SCREEN)
        session.commit()
        return Screen(reply or "Too many checks from this phone: try again in an hour.", more=False)
    if first in ("2", "3") and phone is None:
        return Screen("Reminders go only to a phone number the gateway can name.", more=False)
    assert phone is not None or first not in ("2", "3")
    if first == "2":
        if not rest:
            return Screen(ASK_REMIND, more=True)
        return Screen(_remind(session, phone or "", rest[:QUERY_LENGTH], settings, now), more=False)
    if first == "3":
        return Screen(_stopped(service.stop_phone(session, phone or "", now), phone or ""), more=False)
    return Screen(f"Choose 1, 2 or 3. {ASK}", more=False)


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
    keyword, _, rest = words.partition(" ")
    keyword = keyword.upper()
    reply: str | None
    if keyword in ("STOP", "UNSUBSCRIBE", "END", "CANCEL") and not rest:
        reply = _stopped(service.stop_phone(session, phone, now), phone)
    elif keyword == "REMIND":
        reply = _remind(session, phone, rest, settings, now, key)
        if reply.startswith("A code was sent"):
            return reply  # the code itself is the answer
    elif _CODE.fullmatch(words.upper()):
        match = _CODE.fullmatch(words.upper())
        assert match is not None
        confirmed = service.confirm_code(session, phone, match[1], now)
        if confirmed is None:
            reply = "That code is wrong or too old: send REMIND and the plate again."
        else:
            vehicle = service.vehicle_of(session, confirmed)
            reply = (
                f"Reminders for {vehicle} confirmed: 30 and 7 days before its certificate expires, "
                "and a day after. Reply STOP to end."
            )
    else:
        query = rest if keyword == "CHECK" else words
        reply = _check(session, phone, query, settings, now, None) if query else ASK
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
