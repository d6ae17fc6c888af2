"""Sign-in attempts: logged to a table and the Python log (never the password), and the lock-out rule."""

from __future__ import annotations

import logging
from datetime import timedelta

from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.accounts.models import LoginAttempt
from app.config import Settings
from app.db import utcnow

log = logging.getLogger("trikecert.accounts.login")

SUCCESS = "success"
BAD_CREDENTIALS = "bad_credentials"
LOCKED_OUT = "locked_out"
DISABLED = "disabled"
# An office behind one address may hold several officers: allow it this many times one account's failures.
ADDRESS_FACTOR = 4


def record_attempt(
    session: Session, *, email: str, outcome: str, user_id: int | None, client_ip: str | None
) -> None:
    """Store one attempt and log it."""
    session.add(LoginAttempt(email=email[:254], user_id=user_id, client_ip=client_ip, outcome=outcome))
    session.commit()
    level = logging.INFO if outcome == SUCCESS else logging.WARNING
    log.log(level, "sign-in %s for %r from %s", outcome, email[:254], client_ip or "unknown address")


def recent_failures(session: Session, *, email: str, settings: Settings) -> int:
    """Failed attempts for this email within the lock-out window and since its last success."""
    since = utcnow() - timedelta(minutes=settings.login_lockout_minutes)
    last_success = session.scalar(
        select(func.max(LoginAttempt.created_at)).where(
            LoginAttempt.email == email, LoginAttempt.outcome == SUCCESS, LoginAttempt.created_at >= since
        )
    )
    query = select(func.count()).where(
        LoginAttempt.email == email,
        LoginAttempt.outcome == BAD_CREDENTIALS,
        LoginAttempt.created_at >= since,
    )
    if last_success is not None:
        query = query.where(LoginAttempt.created_at > last_success)
    return int(session.scalar(query) or 0)


def address_failures(session: Session, *, client_ip: str, settings: Settings) -> int:
    """Failed attempts from this address within the lock-out window, whatever the email."""
    since = utcnow() - timedelta(minutes=settings.login_lockout_minutes)
    query = select(func.count()).where(
        LoginAttempt.client_ip == client_ip,
        LoginAttempt.outcome == BAD_CREDENTIALS,
        LoginAttempt.created_at >= since,
    )
    return int(session.scalar(query) or 0)


def is_locked_out(session: Session, *, email: str, client_ip: str | None, settings: Settings) -> bool:
    """True when the email has reached the allowed failures within the window, or the address has
    reached several times that many (one address trying password after password on many accounts)."""
    if recent_failures(session, email=email, settings=settings) >= settings.login_max_failures:
        return True
    limit = settings.login_max_failures * ADDRESS_FACTOR
    return (
        client_ip is not None and address_failures(session, client_ip=client_ip, settings=settings) >= limit
    )
