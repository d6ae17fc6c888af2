"""Server-side browser sessions: a random cookie, only its hash stored, idle and absolute timeouts."""

from __future__ import annotations

import hashlib
import secrets
from dataclasses import dataclass
from datetime import timedelta

from sqlalchemy import delete, select
from sqlalchemy.orm import Session

from app.accounts.models import User, UserSession
from app.config import Settings
from app.db import utcnow

# Touching last_seen_at on every request would write on every page view; once a minute is enough.
TOUCH_INTERVAL = timedelta(seconds=60)


def hash_token(token: str) -> str:
    """SHA-256 of a session token: the token carries 256 random bits, so a fast hash is safe."""
    return hashlib.sha256(token.encode()).hexdigest()


@dataclass(frozen=True)
class NewSession:
    """A session just started: the cookie value is known only here and in the browser."""

    token: str
    record: UserSession


def start_session(session: Session, *, user: User, settings: Settings) -> NewSession:
    """Start a session for the user with a fresh random id; expired sessions of the user are swept."""
    now = utcnow()
    session.execute(delete(UserSession).where(UserSession.user_id == user.id, UserSession.expires_at <= now))
    token = secrets.token_urlsafe(32)
    record = UserSession(
        token_hash=hash_token(token),
        user_id=user.id,
        csrf_token=secrets.token_urlsafe(32),
        created_at=now,
        last_seen_at=now,
        verified_at=now,
        expires_at=now + timedelta(hours=settings.session_absolute_hours),
    )
    session.add(record)
    session.commit()
    return NewSession(token=token, record=record)


def load_session(session: Session, *, token: str, settings: Settings) -> UserSession | None:
    """The live session for this cookie value, or None; an expired or disabled one is ended here."""
    record = session.scalar(select(UserSession).where(UserSession.token_hash == hash_token(token)))
    if record is None:
        return None
    now = utcnow()
    idle = timedelta(minutes=settings.session_idle_minutes)
    if not record.user.active or now >= record.expires_at or now - record.last_seen_at >= idle:
        session.delete(record)
        session.commit()
        return None
    if now - record.last_seen_at >= TOUCH_INTERVAL:
        record.last_seen_at = now
        session.commit()
    return record


def end_session(session: Session, *, token: str) -> None:
    """End the session with this cookie value on the server, so a replayed cookie no longer works."""
    session.execute(delete(UserSession).where(UserSession.token_hash == hash_token(token)))
    session.commit()


def end_user_sessions(session: Session, *, user_id: int, keep_id: int | None = None) -> int:
    """End every session of a user (except `keep_id`); returns how many were ended."""
    query = delete(UserSession).where(UserSession.user_id == user_id)
    if keep_id is not None:
        query = query.where(UserSession.id != keep_id)
    ended = session.execute(query).rowcount  # type: ignore[attr-defined]
    session.commit()
    return int(ended or 0)


def set_flash(session: Session, record: UserSession, message: str) -> None:
    """Keep one message to show on the next page."""
    record.flash = message[:500]
    session.commit()


def pop_flash(session: Session, record: UserSession) -> str | None:
    """The pending message, cleared once read."""
    message = record.flash
    if message is not None:
        record.flash = None
        session.commit()
    return message
