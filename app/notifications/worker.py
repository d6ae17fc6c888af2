"""`trikecert notify`: plan the reminders due, then send the outbox, one claimed message at a time.

A claim is a row update (on PostgreSQL under FOR UPDATE SKIP LOCKED): two workers never hold the same
message. A message is marked sent right after the gateway or mail server accepts it; a worker that
dies in between leaves its claim to lapse, and the message is sent again: at most one duplicate per
crash (docs/notifications.md).
"""

from __future__ import annotations

import logging
import smtplib
import ssl
import time
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from datetime import datetime, timedelta
from email.message import EmailMessage
from email.utils import make_msgid
from typing import Protocol
from urllib.parse import unquote, urlsplit

from sqlalchemy import delete, or_, select, update
from sqlalchemy.orm import Session, sessionmaker

from app.config import Settings
from app.db import utcnow
from app.notifications.models import GatewayCheck, OutboxMessage
from app.notifications.service import bump, plan_reminders

log = logging.getLogger("trikecert.notify")
BACKOFF_FIRST = timedelta(seconds=30)
BACKOFF_MOST = timedelta(hours=6)


class SendFailed(Exception):
    """A send that did not go through; `permanent` when trying again cannot help."""

    def __init__(self, reason: str, *, permanent: bool) -> None:
        super().__init__(reason)
        self.reason = reason[:300]
        self.permanent = permanent


class Sender(Protocol):
    """Sends one outbox message over its channel: the provider's id, or SendFailed."""

    def send(self, message: OutboxMessage) -> str | None:
        """Send it."""


@dataclass
class Pass:
    """What one pass did."""

    planned: int = 0
    sent: int = 0
    retried: int = 0
    failed: int = 0


def lease(settings: Settings) -> timedelta:
    """How long a claim holds: longer than one send may take, so a live worker never loses its claim."""
    return timedelta(seconds=2 * settings.notify_timeout_seconds + 1)


def backoff(attempts: int) -> timedelta:
    """The wait before the next try: 30 s, doubling, at most 6 hours."""
    wait: timedelta = BACKOFF_FIRST * (2 ** max(0, attempts - 1))
    return min(wait, BACKOFF_MOST)


def claim(session: Session, channels: set[str], settings: Settings, now: datetime) -> OutboxMessage | None:
    """Claim the oldest due message of these channels for this worker, or None when none is due."""
    token = uuid.uuid4().hex
    due = (
        select(OutboxMessage.id)
        .where(
            OutboxMessage.sent_at.is_(None),
            OutboxMessage.failed_at.is_(None),
            OutboxMessage.recipient.is_not(None),
            OutboxMessage.channel.in_(sorted(channels)),
            OutboxMessage.next_attempt_at <= now,
            or_(OutboxMessage.claimed_until.is_(None), OutboxMessage.claimed_until < now),
        )
        .order_by(OutboxMessage.id)
        .limit(1)
    )
    lapsed = or_(OutboxMessage.claimed_until.is_(None), OutboxMessage.claimed_until < now)
    if session.get_bind().dialect.name == "postgresql":
        # Lock the row first, then claim it by id: inside `UPDATE ... WHERE id IN (SELECT ... SKIP
        # LOCKED)` the subquery may run again for each row and claim several at once.
        found = session.scalar(due.with_for_update(skip_locked=True))
        if found is None:
            session.commit()
            return None
        target = OutboxMessage.id == found
    else:
        # On SQLite the one statement is atomic (a write locks the file); its conditions are checked
        # again in the outer WHERE, so a row claimed meanwhile is not claimed twice.
        target = OutboxMessage.id == due.scalar_subquery()
    claimed = session.execute(
        update(OutboxMessage)
        .where(target, lapsed, OutboxMessage.sent_at.is_(None))
        .values(claim=token, claimed_until=now + lease(settings))
        .execution_options(synchronize_session=False)
    )
    session.commit()
    if claimed.rowcount == 0:  # type: ignore[attr-defined]
        return None
    return session.scalar(select(OutboxMessage).where(OutboxMessage.claim == token))


def _record(session: Session, message: OutboxMessage, values: dict[str, object]) -> bool:
    done = session.execute(
        update(OutboxMessage)
        .where(OutboxMessage.id == message.id, OutboxMessage.claim == message.claim)
        .values(claim=None, claimed_until=None, **values)
        .execution_options(synchronize_session=False)
    )
    return bool(done.rowcount)  # type: ignore[attr-defined]


def deliver(
    session: Session, message: OutboxMessage, sender: Sender, settings: Settings, now: datetime, result: Pass
) -> None:
    """Send one claimed message and record what happened, in one transaction with its count."""
    attempts = message.attempts + 1
    try:
        reference = sender.send(message)
    except SendFailed as failed:
        given_up = failed.permanent or attempts >= settings.notify_max_attempts
        if given_up:
            _record(
                session,
                message,
                {"attempts": attempts, "failed_at": now, "recipient": None, "last_error": failed.reason},
            )
            bump(session, "failed", now)
            result.failed += 1
        else:
            _record(
                session,
                message,
                {
                    "attempts": attempts,
                    "next_attempt_at": now + backoff(attempts),
                    "last_error": failed.reason,
                },
            )
            result.retried += 1
        log.warning(
            "message %s to %s %s: %s",
            message.id,
            message.recipient_masked,
            "failed" if given_up else "will be retried",
            failed.reason,
        )
        session.commit()
        return
    _record(
        session, message, {"attempts": attempts, "sent_at": now, "recipient": None, "provider_ref": reference}
    )
    bump(session, "sent", now)
    session.commit()
    result.sent += 1
    log.info("message %s (%s) sent to %s", message.id, message.purpose, message.recipient_masked)


def prune(session: Session, settings: Settings, now: datetime) -> None:
    """Delete messages done longer ago than the retention, and checks older than a day."""
    cutoff = now - timedelta(days=settings.notify_keep_days)
    session.execute(
        delete(OutboxMessage).where(or_(OutboxMessage.sent_at < cutoff, OutboxMessage.failed_at < cutoff))
    )
    session.execute(delete(GatewayCheck).where(GatewayCheck.at < now - timedelta(days=1)))
    session.commit()


def run_once(
    sessions: sessionmaker[Session],
    senders: Mapping[str, Sender],
    settings: Settings,
    now: Callable[[], datetime] = utcnow,
    limit: int | None = None,
) -> Pass:
    """One pass: plan the reminders due, send every due message a sender is configured for, prune."""
    result = Pass()
    with sessions() as session:
        result.planned = plan_reminders(session, settings, now())
        channels = set(senders)
        sent_here = 0
        while channels and (limit is None or sent_here < limit):
            message = claim(session, channels, settings, now())
            if message is None:
                break
            deliver(session, message, senders[message.channel], settings, now(), result)
            sent_here += 1
        prune(session, settings, now())
    return result


def run(
    sessions: sessionmaker[Session], senders: Mapping[str, Sender], settings: Settings, once: bool = False
) -> None:
    """Passes every `notify_interval_seconds` until stopped (or just one)."""
    while True:
        try:
            done = run_once(sessions, senders, settings)
            if done.planned or done.sent or done.failed or done.retried:
                log.info(
                    "pass: %s planned, %s sent, %s to retry, %s failed",
                    done.planned,
                    done.sent,
                    done.retried,
                    done.failed,
                )
        except Exception:  # a database outage: the next pass tries again
            if once:
                raise
            log.exception("notify pass failed; trying again in %s s", settings.notify_interval_seconds)
        if once:
            return
        time.sleep(settings.notify_interval_seconds)


class SmtpSender:
    """Sends an outbox email over SMTP: STARTTLS when the server offers it (smtps:// for TLS at once)."""

    def __init__(self, url: str, mail_from: str, timeout: float) -> None:
        self.parts = urlsplit(url)
        self.mail_from = mail_from
        self.timeout = timeout

    def _connect(self) -> smtplib.SMTP:
        host = self.parts.hostname or "localhost"
        context = ssl.create_default_context()
        if self.parts.scheme == "smtps":
            return smtplib.SMTP_SSL(host, self.parts.port or 465, timeout=self.timeout, context=context)
        server = smtplib.SMTP(host, self.parts.port or 587, timeout=self.timeout)
        server.ehlo()
        if server.has_extn("starttls"):
            server.starttls(context=context)
            server.ehlo()
        return server

    def email(self, message: OutboxMessage) -> EmailMessage:
        """The message as sent: with List-Unsubscribe (one click, RFC 8058) when it has a link."""
        email = EmailMessage()
        email["From"] = self.mail_from
        email["To"] = message.recipient or ""
        email["Subject"] = message.subject or "trikecert"
        email["Message-ID"] = make_msgid(domain="trikecert")
        if message.unsubscribe_url:
            email["List-Unsubscribe"] = f"<{message.unsubscribe_url}>"
            email["List-Unsubscribe-Post"] = "List-Unsubscribe=One-Click"
        email.set_content(message.body)
        return email

    def send(self, message: OutboxMessage) -> str | None:
        """Hand the message to the server; a 5xx refusal is permanent, anything else is tried again."""
        email = self.email(message)
        try:
            with self._connect() as server:
                if self.parts.username:
                    server.login(unquote(self.parts.username), unquote(self.parts.password or ""))
                server.send_message(email)
        except smtplib.SMTPRecipientsRefused as refused:
            codes = [code for code, _text in refused.recipients.values()]
            raise SendFailed(f"recipient refused: {codes}", permanent=all(c >= 500 for c in codes)) from None
        except smtplib.SMTPResponseException as error:
            raise SendFailed(
                f"mail server answered {error.smtp_code}", permanent=error.smtp_code >= 500
            ) from None
        except (TimeoutError, smtplib.SMTPException, OSError) as error:
            raise SendFailed(f"mail server unreachable: {type(error).__name__}", permanent=False) from None
        return str(email["Message-ID"])[:120]
