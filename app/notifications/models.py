"""The tables of reminders: who asked to be reminded about which plate, the outbox of messages to
send, a log of checks for the per-phone limit, and the counts admins see (no contacts)."""

from __future__ import annotations

from datetime import date, datetime

from sqlalchemy import (
    CheckConstraint,
    Date,
    ForeignKey,
    Integer,
    String,
    Text,
    UniqueConstraint,
)
from sqlalchemy.orm import Mapped, mapped_column

from app.db import Base, UTCDateTime, utcnow

CHANNELS = ("sms", "email")
PURPOSES = ("confirm", "reminder_30", "reminder_7", "reminder_after", "reply")


class Subscription(Base):
    """One contact's wish to be reminded about one vehicle; deleted, contact and all, on unsubscribe."""

    __tablename__ = "notification_subscription"
    __table_args__ = (
        UniqueConstraint("vehicle_id", "channel", "contact"),
        CheckConstraint("channel IN ('sms', 'email')", name="channel"),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    vehicle_id: Mapped[int] = mapped_column(ForeignKey("vehicle.id"), index=True)
    channel: Mapped[str] = mapped_column(String(8))
    contact: Mapped[str] = mapped_column(String(254))  # E.164 or an email address: needed to send
    contact_digest: Mapped[str] = mapped_column(String(64), index=True)
    # The secret of its links (confirm, unsubscribe): random, dies with the row.
    token: Mapped[str] = mapped_column(String(64), unique=True)
    code_hash: Mapped[str | None] = mapped_column(String(64))  # an SMS confirmation code, hashed
    code_failures: Mapped[int] = mapped_column(Integer, default=0)
    confirmed_at: Mapped[datetime | None] = mapped_column(UTCDateTime())
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    # The language the subscriber asked in ('ha', ...): its confirmation and reminders speak it.
    language: Mapped[str | None] = mapped_column(String(8))


class PhoneLanguage(Base):
    """The language a phone chose (SMS LANG, USSD 4) for its replies and reminder SMS, by its digest."""

    __tablename__ = "notification_phone_language"

    phone_digest: Mapped[str] = mapped_column(String(64), primary_key=True)
    language: Mapped[str] = mapped_column(String(8))
    chosen_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)


class OutboxMessage(Base):
    """One message to send, written with the decision to send it; its recipient is erased once done."""

    __tablename__ = "notification_outbox"
    __table_args__ = (
        CheckConstraint("channel IN ('sms', 'email')", name="channel"),
        CheckConstraint(
            "purpose IN ('confirm', 'reminder_30', 'reminder_7', 'reminder_after', 'reply')", name="purpose"
        ),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    subscription_id: Mapped[int | None] = mapped_column(
        ForeignKey("notification_subscription.id", ondelete="SET NULL"), index=True
    )
    channel: Mapped[str] = mapped_column(String(8))
    purpose: Mapped[str] = mapped_column(String(16))
    recipient: Mapped[str | None] = mapped_column(String(254))  # None once sent, failed or unsubscribed
    recipient_masked: Mapped[str] = mapped_column(String(64))
    recipient_digest: Mapped[str] = mapped_column(String(64), index=True)
    requested_by: Mapped[str | None] = mapped_column(String(64), index=True)  # a client address, digested
    subject: Mapped[str | None] = mapped_column(String(200))
    body: Mapped[str] = mapped_column(Text)
    unsubscribe_url: Mapped[str | None] = mapped_column(String(300))
    # At most one message per key: a reminder per subscription, certificate and stage; a reply per
    # incoming message (a replayed callback finds its key taken).
    dedupe_key: Mapped[str | None] = mapped_column(String(120), unique=True)
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow, index=True)
    next_attempt_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    attempts: Mapped[int] = mapped_column(Integer, default=0)
    claim: Mapped[str | None] = mapped_column(String(40))
    claimed_until: Mapped[datetime | None] = mapped_column(UTCDateTime())
    sent_at: Mapped[datetime | None] = mapped_column(UTCDateTime())
    failed_at: Mapped[datetime | None] = mapped_column(UTCDateTime())
    last_error: Mapped[str | None] = mapped_column(String(300))
    provider_ref: Mapped[str | None] = mapped_column(String(120))


class GatewayCheck(Base):
    """One check by USSD or SMS: only the phone's digest and when, for the per-phone limit."""

    __tablename__ = "notification_check"

    id: Mapped[int] = mapped_column(primary_key=True)
    phone_digest: Mapped[str] = mapped_column(String(64), index=True)
    at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow, index=True)


class NotificationDay(Base):
    """How many subscriptions were confirmed, messages sent and failed on one day: counts, no contacts."""

    __tablename__ = "notification_day"

    day: Mapped[date] = mapped_column(Date, primary_key=True)
    what: Mapped[str] = mapped_column(String(16), primary_key=True)
    count: Mapped[int] = mapped_column(Integer, default=0)
