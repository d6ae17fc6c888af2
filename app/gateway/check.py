"""One answer to 'what does this plate or certificate number hold now?', in the verify page's words
(app/wording.py, app/certificates/wording.py) shortened to one SMS or one USSD screen."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from datetime import datetime

from sqlalchemy import select
from sqlalchemy.orm import Session

from app.certificates.facts import Facts
from app.certificates.in_force import current_document
from app.certificates.models import Certificate
from app.certificates.records import certificate_status, find_certificate
from app.certificates.wording import lapsed_sentence, not_on_record, sentence, until_sentence
from app.i18n.active import gettext as _
from app.notifications.messages import short_date
from app.notifications.sms_text import first_fitting
from app.trust.numbers import PREFIX, InvalidNumber, normalise, parse_number
from app.vehicles.service import display_registration, find_vehicle, lookup_key
from app.web.formatting import long_date
from app.wording import document_kind, status_headline_on


def ask() -> str:
    """How to write what a check needs."""
    return _("Send a plate like BDG 252 QH or a certificate number like TRK-2026-000123-K.")


@dataclass(frozen=True)
class Found:
    """What a query found: a vehicle's plate and its newest document, or only the plate."""

    plate: str
    certificate: Certificate | None
    vehicle_id: int | None


def _newest(session: Session, vehicle_id: int, now: datetime) -> Certificate | None:
    """The document in force (or expired), else the vehicle's newest one (a revoked one)."""
    current = current_document(session, vehicle_id, now)
    if current is not None:
        return current.certificate
    query = select(Certificate).where(Certificate.vehicle_id == vehicle_id).order_by(Certificate.id.desc())
    return session.scalars(query.limit(1)).first()


def is_number(query: str) -> bool:
    """True when the text is meant as a certificate number (it starts TRK), not a plate."""
    return normalise(query).startswith(PREFIX) and any(char.isdigit() for char in query)


def _since(certificate: Certificate, status: str) -> datetime | None:
    if status == "revoked" and certificate.revocation is not None:
        return certificate.revocation.revoked_at
    if status == "superseded" and certificate.superseded_by is not None:
        return certificate.superseded_by.issued_at
    if status == "expired":
        return certificate.expires_at
    return None


def _document_texts(certificate: Certificate, now: datetime) -> Iterator[str]:
    """The document's answer, longest first: long dates and its number, then shorter forms."""
    status = certificate_status(certificate, now)
    kind = certificate.kind
    since = _since(certificate, status)
    plate = certificate.registration_number
    number = f"{document_kind(kind).capitalize()} {certificate.number}."
    if status == "issued":
        detail = sentence(Facts.from_json(certificate.facts).occupancy)
    else:
        detail = lapsed_sentence(kind, status)
    newer = certificate.superseded_by if status == "superseded" else None
    for date_words in (long_date, short_date):
        headline = status_headline_on(kind, status, date_words(since) if since else None)
        parts = [f"{plate}: {headline}.", detail]
        if status == "issued":
            parts.append(until_sentence(kind, date_words(certificate.expires_at)))
        if newer is not None:
            if newer.kind == "compliant":
                parts.append(_("Only certificate %(number)s counts.") % {"number": newer.number})
            else:
                parts.append(_("Only refusal %(number)s counts.") % {"number": newer.number})
        yield " ".join([*parts, number])
        yield " ".join(parts)
    # A translation may still be longer than one SMS: drop the end date, then the detail (a refusal's
    # headline says it certifies nothing), never the plate and the headline.
    headline = status_headline_on(kind, status, short_date(since) if since else None)
    yield f"{plate}: {headline}. {detail}"
    if status == "issued":
        yield f"{plate}: {headline}. {until_sentence(kind, short_date(certificate.expires_at))}"
    yield f"{plate}: {headline}."


def find(session: Session, query: str, now: datetime) -> Found | str:
    """The plate or number's document, or the words saying why nothing is found."""
    text = " ".join(query.split())[:80]
    if is_number(text):
        try:
            canonical = str(parse_number(text))
        except InvalidNumber as error:
            if error.rule == "check_letter":
                return f"{sentence(str(error))}"
            return ask()
        certificate = find_certificate(session, canonical)
        if certificate is None:
            return sentence(not_on_record(canonical))
        return Found(certificate.registration_number, certificate, certificate.vehicle_id)
    if lookup_key(text) is None:
        return ask()
    vehicle = find_vehicle(session, text)
    if vehicle is None:
        return not_registered(display_registration(text))
    return Found(vehicle.registration_number, _newest(session, vehicle.id, now), vehicle.id)


def not_registered(plate: str) -> str:
    """A plate no vehicle has: say so, and how to try again."""
    return _("No keke %(plate)s is registered: check the plate and send it again.") % {"plate": plate}


def no_document(plate: str) -> str:
    """A registered vehicle that has neither a certificate nor a refusal."""
    return _("%(plate)s: NOT CERTIFIED. No certificate or refusal is on record.") % {"plate": plate}


def answer(session: Session, query: str, now: datetime, screen: int | None = None) -> str:
    """The reply to a check: one SMS (or one USSD screen of `screen` characters), never longer."""
    found = find(session, query, now)
    if isinstance(found, str):
        return first_fitting([found], screen)
    if found.certificate is None:
        return first_fitting([no_document(found.plate)], screen)
    return first_fitting(_document_texts(found.certificate, now), screen)
