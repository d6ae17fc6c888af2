"""Subscribe, confirm, unsubscribe and stop; decide reminders; every message into the outbox in the
same transaction as the decision to send it."""

from __future__ import annotations

import hashlib
import hmac
import secrets
import typing
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any

from sqlalchemy import (
    ColumnElement,
    Select,
    String,
    Subquery,
    Table,
    cast,
    delete,
    func,
    literal,
    select,
    update,
)
from sqlalchemy.dialects.postgresql import insert as pg_insert
from sqlalchemy.dialects.sqlite import insert as sqlite_insert
from sqlalchemy.orm import Load, Session

from app.certificates.in_force import in_force_of
from app.certificates.models import Certificate
from app.config import Settings
from app.db import utcnow
from app.i18n.active import use_locale
from app.i18n.locales import ENGLISH, LOCALES
from app.notifications import messages
from app.notifications.contacts import digest, mask
from app.notifications.languages import chosen_languages
from app.notifications.models import GatewayCheck, NotificationDay, OutboxMessage, Subscription
from app.vehicles.models import Vehicle
from app.web.formatting import to_local

CODE_FAILURES = 5  # wrong codes before the pending subscription is dropped
CODE_MINUTES = 30
DAY = timedelta(days=1)
REMINDER_STAGES = ("reminder_30", "reminder_7", "reminder_after")
# The outbox as a table: its insert of many rows is one statement; the ORM's insert with RETURNING
# and ON CONFLICT goes row by row.
_OUTBOX = typing.cast(Table, OutboxMessage.__table__)


class LimitReached(Exception):
    """Too many confirmations to this contact or from this address, or checks from this phone."""


@dataclass(frozen=True)
class Subscribed:
    """What a request for reminders did: a confirmation sent, or nothing (already confirmed)."""

    subscription: Subscription
    confirmation_sent: bool


def _code_hash(token: str, code: str) -> str:
    return hashlib.sha256(f"{token}:{code}".encode()).hexdigest()


def bump(session: Session, what: str, now: datetime, by: int = 1) -> None:
    """Add to a day's count (subscribed, unsubscribed, sent, failed) in the caller's transaction."""
    day = to_local(now).date()
    dialect = session.get_bind().dialect.name
    insert = pg_insert if dialect == "postgresql" else sqlite_insert
    statement = insert(NotificationDay).values(day=day, what=what, count=by)
    session.execute(
        statement.on_conflict_do_update(
            index_elements=["day", "what"], set_={"count": NotificationDay.count + by}
        )
    )


def _sent_lately(session: Session, column: Any, value: str, now: datetime) -> int:
    query = select(func.count()).where(
        column == value,
        OutboxMessage.purpose == "confirm",
        OutboxMessage.created_at > now - DAY,
    )
    return int(session.scalar(query) or 0)


def _outbox_row(
    *,
    channel: str,
    recipient: str,
    purpose: str,
    text: messages.Text,
    subscription_id: int | None,
    dedupe_key: str | None,
    requested_by: str | None = None,
    unsubscribe_url: str | None = None,
    now: datetime,
) -> dict[str, Any]:
    """An outbox row's columns: the recipient masked and digested beside it, due at once."""
    return {
        "subscription_id": subscription_id,
        "channel": channel,
        "purpose": purpose,
        "recipient": recipient,
        "recipient_masked": mask(channel, recipient),
        "recipient_digest": digest(recipient),
        "requested_by": requested_by,
        "subject": text.subject,
        "body": text.body,
        "unsubscribe_url": unsubscribe_url,
        "dedupe_key": dedupe_key,
        "created_at": now,
        "next_attempt_at": now,
    }


def enqueue(
    session: Session,
    *,
    channel: str,
    recipient: str,
    purpose: str,
    text: messages.Text,
    subscription: Subscription | None = None,
    dedupe_key: str | None = None,
    requested_by: str | None = None,
    unsubscribe_url: str | None = None,
    now: datetime | None = None,
) -> OutboxMessage:
    """Add a message to the outbox (the caller commits it with its decision)."""
    row = _outbox_row(
        channel=channel,
        recipient=recipient,
        purpose=purpose,
        text=text,
        subscription_id=subscription.id if subscription is not None else None,
        dedupe_key=dedupe_key,
        requested_by=requested_by,
        unsubscribe_url=unsubscribe_url,
        now=now or utcnow(),
    )
    message = OutboxMessage(**row)
    session.add(message)
    return message


def link(settings: Settings, action: str, token: str) -> str:
    """A subscription's confirm or unsubscribe address."""
    return f"{settings.base_url.rstrip('/')}/reminders/{action}/{token}"


def subscribe(
    session: Session,
    *,
    vehicle: Vehicle,
    channel: str,
    contact: str,
    client: str,
    settings: Settings,
    now: datetime | None = None,
    dedupe_key: str | None = None,
    language: str | None = None,
) -> Subscribed:
    """Ask for reminders about a vehicle: a code (SMS) or a link (email) goes to the contact first,
    in the language asked in (kept for the reminders).

    LimitReached when this contact, or this client address, has had its confirmations for the day.
    """
    now = now or utcnow()
    existing = session.scalar(
        select(Subscription).where(
            Subscription.vehicle_id == vehicle.id,
            Subscription.channel == channel,
            Subscription.contact == contact,
        )
    )
    if existing is not None and existing.confirmed_at is not None:
        return Subscribed(existing, confirmation_sent=False)
    requested_by = digest(client)
    if (
        _sent_lately(session, OutboxMessage.recipient_digest, digest(contact), now)
        >= settings.confirmations_per_contact
        or _sent_lately(session, OutboxMessage.requested_by, requested_by, now)
        >= settings.confirmations_per_address
    ):
        raise LimitReached
    subscription = existing or Subscription(
        vehicle_id=vehicle.id,
        channel=channel,
        contact=contact,
        contact_digest=digest(contact),
        token=secrets.token_urlsafe(32),
        created_at=now,
    )
    subscription.language = language if language in LOCALES else None
    session.add(subscription)
    session.flush()
    with use_locale(subscription.language or ENGLISH):
        if channel == "sms":
            code = f"{secrets.randbelow(10**6):06d}"
            subscription.code_hash = _code_hash(subscription.token, code)
            subscription.code_failures = 0
            subscription.created_at = now  # the code's age
            text = messages.confirm_sms(vehicle.registration_number, code)
        else:
            text = messages.confirm_email(
                vehicle.registration_number, link(settings, "confirm", subscription.token)
            )
    enqueue(
        session,
        channel=channel,
        recipient=contact,
        purpose="confirm",
        text=text,
        subscription=subscription,
        requested_by=requested_by,
        dedupe_key=dedupe_key,
        now=now,
    )
    session.commit()
    return Subscribed(subscription, confirmation_sent=True)


def _confirmed(session: Session, subscription: Subscription, now: datetime) -> None:
    subscription.confirmed_at = now
    subscription.code_hash = None
    bump(session, "subscribed", now)


def confirm_code(session: Session, phone: str, code: str, now: datetime | None = None) -> Subscription | None:
    """Confirm the phone's pending subscription whose code this is; None (and a failure counted) if none."""
    now = now or utcnow()
    pending = session.scalars(
        select(Subscription).where(
            Subscription.channel == "sms",
            Subscription.contact == phone,
            Subscription.confirmed_at.is_(None),
            Subscription.code_hash.is_not(None),
        )
    ).all()
    for subscription in pending:
        fresh = subscription.created_at > now - timedelta(minutes=CODE_MINUTES)
        expected = subscription.code_hash or ""
        if fresh and hmac.compare_digest(_code_hash(subscription.token, code), expected):
            _confirmed(session, subscription, now)
            session.commit()
            return subscription
    for subscription in pending:
        subscription.code_failures += 1
        if subscription.code_failures >= CODE_FAILURES:
            _drop(session, subscription)
    session.commit()
    return None


def confirm_link(session: Session, token: str, now: datetime | None = None) -> Subscription | None:
    """Confirm the email subscription of this link; None when the link is unknown (or unsubscribed)."""
    subscription = session.scalar(select(Subscription).where(Subscription.token == token))
    if subscription is None:
        return None
    if subscription.confirmed_at is None:
        _confirmed(session, subscription, now or utcnow())
        session.commit()
    return subscription


def _drop(session: Session, subscription: Subscription) -> None:
    """Delete a subscription and every message to it not yet sent; the sent ones keep no recipient."""
    session.execute(
        delete(OutboxMessage).where(
            OutboxMessage.subscription_id == subscription.id,
            OutboxMessage.sent_at.is_(None),
            OutboxMessage.failed_at.is_(None),
        )
    )
    session.execute(
        update(OutboxMessage)
        .where(OutboxMessage.subscription_id == subscription.id)
        .values(recipient=None, subscription_id=None)
    )
    session.delete(subscription)


def unsubscribe(session: Session, token: str, now: datetime | None = None) -> str | None:
    """End the subscription of this link: the plate it was about, or None when there is none."""
    subscription = session.scalar(select(Subscription).where(Subscription.token == token))
    if subscription is None:
        return None
    vehicle = session.get(Vehicle, subscription.vehicle_id)
    _drop(session, subscription)
    bump(session, "unsubscribed", now or utcnow())
    session.commit()
    return vehicle.registration_number if vehicle is not None else ""


def stop_phone(session: Session, phone: str, now: datetime | None = None) -> int:
    """STOP: every subscription of this phone deleted and nothing more sent to it; how many there were."""
    found = session.scalars(
        select(Subscription).where(Subscription.channel == "sms", Subscription.contact == phone)
    ).all()
    for subscription in found:
        _drop(session, subscription)
    session.execute(
        delete(OutboxMessage).where(
            OutboxMessage.recipient_digest == digest(phone),
            OutboxMessage.channel == "sms",
            OutboxMessage.sent_at.is_(None),
            OutboxMessage.failed_at.is_(None),
        )
    )
    if found:
        bump(session, "unsubscribed", now or utcnow(), by=len(found))
    session.commit()
    return len(found)


def check_allowed(session: Session, phone: str, settings: Settings, now: datetime | None = None) -> bool:
    """Count a check by this phone; False when it has made its checks for the hour (nothing counted)."""
    now = now or utcnow()
    key = digest(phone)
    made = session.scalar(
        select(func.count()).where(
            GatewayCheck.phone_digest == key, GatewayCheck.at > now - timedelta(hours=1)
        )
    )
    if int(made or 0) >= settings.checks_per_phone:
        return False
    session.add(GatewayCheck(phone_digest=key, at=now))
    return True


def key_taken(session: Session, dedupe_key: str) -> bool:
    """True when the outbox holds this key: a reminder already decided, or a callback already answered."""
    return session.scalar(select(OutboxMessage.id).where(OutboxMessage.dedupe_key == dedupe_key)) is not None


def stage_due(expires_at: datetime, now: datetime) -> str | None:
    """The reminder due now for a certificate expiring then: 30 days, 7 days before, or 1 day after."""
    if expires_at - timedelta(days=30) <= now < expires_at - timedelta(days=7):
        return "reminder_30"
    if expires_at - timedelta(days=7) <= now < expires_at:
        return "reminder_7"
    if expires_at + DAY <= now < expires_at + timedelta(days=31):
        return "reminder_after"
    return None


def _due_pairs(now: datetime) -> Select[int, int]:
    """Each confirmed subscription with its vehicle's document in force when that is a certificate (a
    refusal triggers none) whose expiry puts a stage within reach now: (subscription_id, certificate_id).
    The window is every stage's together (30 days before to 31 after); `stage_due` decides."""
    confirmed = Subscription.confirmed_at.is_not(None)
    in_force = in_force_of(select(Subscription.vehicle_id).where(confirmed)).subquery()
    return (
        select(Subscription.id.label("subscription_id"), Certificate.id.label("certificate_id"))
        .join(in_force, in_force.c.vehicle_id == Subscription.vehicle_id)
        .join(Certificate, Certificate.id == in_force.c.certificate_id)
        .where(confirmed, Certificate.kind == "compliant")
        .where(
            Certificate.expires_at > now - timedelta(days=31),
            Certificate.expires_at <= now + timedelta(days=30),
        )
    )


def _keys_taken(session: Session, pairs: Subquery) -> set[str]:
    """The reminder keys of these pairs the outbox already holds, any stage, in one query."""

    def key(stage: str) -> ColumnElement[str]:
        return (
            literal(f"{stage}:")
            + cast(pairs.c.subscription_id, String)
            + ":"
            + cast(pairs.c.certificate_id, String)
        )

    query = select(OutboxMessage.dedupe_key).join(
        pairs, OutboxMessage.dedupe_key.in_([key(stage) for stage in REMINDER_STAGES])
    )
    return {found for found in session.scalars(query) if found is not None}


def _write_new(session: Session, rows: list[dict[str, Any]]) -> int:
    """Insert these outbox rows, skipping any whose key another worker wrote meanwhile; how many were
    written (the statement is batched by SQLAlchemy, a thousand rows at a time)."""
    dialect = session.get_bind().dialect.name
    insert = pg_insert if dialect == "postgresql" else sqlite_insert
    statement = insert(_OUTBOX).on_conflict_do_nothing(index_elements=["dedupe_key"]).returning(_OUTBOX.c.id)
    return len(session.execute(statement, rows).all())


def plan_reminders(session: Session, settings: Settings, now: datetime | None = None) -> int:
    """Write the reminders due now into the outbox, each at most once per subscription, certificate and
    stage (two workers planning at once collide on that key; one writes it). How many were written.

    A few statements whatever the number of subscriptions: the pairs due, the keys already taken, the
    phones' languages, one insert (each batched when there are thousands)."""
    now = now or utcnow()
    pairs = _due_pairs(now).subquery()
    found = session.execute(
        select(Subscription, Certificate)
        .join(pairs, pairs.c.subscription_id == Subscription.id)
        .join(Certificate, Certificate.id == pairs.c.certificate_id)
        .options(Load(Certificate).lazyload("*"))  # a reminder reads none of its relations
        .order_by(Subscription.id)
    ).all()
    taken = _keys_taken(session, pairs) if found else set()
    due: list[tuple[Subscription, Certificate, str, str]] = []
    for subscription, certificate in found:
        stage = stage_due(certificate.expires_at, now)
        if stage is None:
            continue
        key = f"{stage}:{subscription.id}:{certificate.id}"
        if key not in taken:
            due.append((subscription, certificate, stage, key))
    phones = [subscription.contact for subscription, *_rest in due if subscription.channel == "sms"]
    chosen = chosen_languages(session, phones) if phones else {}
    rows = []
    for subscription, certificate, stage, key in due:
        unsubscribe_url = link(settings, "unsubscribe", subscription.token)
        with use_locale(_language_of(subscription, chosen)):
            if subscription.channel == "sms":
                text = messages.reminder_sms(stage, certificate)
            else:
                verify = f"{settings.base_url.rstrip('/')}/verify/{certificate.number}"
                text = messages.reminder_email(stage, certificate, verify, unsubscribe_url)
        rows.append(
            _outbox_row(
                channel=subscription.channel,
                recipient=subscription.contact,
                purpose=stage,
                text=text,
                subscription_id=subscription.id,
                dedupe_key=key,
                unsubscribe_url=unsubscribe_url if subscription.channel == "email" else None,
                now=now,
            )
        )
    if not rows:
        return 0
    written = _write_new(session, rows)
    session.commit()
    return written


def _language_of(subscription: Subscription, chosen: dict[str, str]) -> str:
    """A reminder's language: a phone's latest choice (SMS LANG, USSD 4), else the one subscribed in."""
    if subscription.channel == "sms" and subscription.contact in chosen:
        return chosen[subscription.contact]
    return subscription.language if subscription.language in LOCALES else ENGLISH


def vehicle_of(session: Session, subscription: Subscription) -> str:
    """The plate a subscription is about, as registered."""
    vehicle = session.get(Vehicle, subscription.vehicle_id)
    return vehicle.registration_number if vehicle is not None else ""
