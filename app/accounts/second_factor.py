"""The second factor of a sign-in: RFC 6238 time-based codes (pyotp) and single-use recovery codes.

A code is accepted at most once: the time step it was accepted for is stored, and a code is taken
only by an UPDATE that moves that step forward, atomically, so two requests carrying the same code
cannot both pass. Code attempts count against the same kind of atomic lock-out as passwords.
"""

from __future__ import annotations

import hashlib
import secrets
import time
from dataclasses import dataclass

import pyotp
import segno
from sqlalchemy import delete, func, or_, select, update
from sqlalchemy.orm import Session

from app.accounts import throttle
from app.accounts.models import RecoveryCode, User, UserSession
from app.audit.recorder import record_event
from app.config import Settings
from app.db import begin_write, utcnow
from app.errors import ServiceError
from app.i18n.active import gettext

STEP_SECONDS = 30
RECOVERY_CODES = 10
# Codes one step either side of now are accepted: a phone's clock a little off, a slow typist.
DRIFT_STEPS = 1


class CodeRefused(ServiceError):
    """The code is wrong, used already, or too many were tried (422 beside the code field)."""

    status = 422


@dataclass(frozen=True)
class Enrolment:
    """What the enrolment page shows: the secret in text and as a QR code for an authenticator app."""

    secret: str
    uri: str
    qr_svg: str


def is_enrolled(user: User) -> bool:
    """True when the account has a confirmed second factor."""
    return user.totp_confirmed_at is not None and user.totp_secret is not None


def needs_second_factor(user: User, settings: Settings) -> bool:
    """True when signing in as this user takes a code: it is enrolled, or the service requires it."""
    return is_enrolled(user) or settings.mfa_mode() == "required"


def passed(record: UserSession, settings: Settings) -> bool:
    """True when this browser session may go on: it passed the second factor, or none is needed."""
    return record.second_factor_at is not None or not needs_second_factor(record.user, settings)


def start_enrolment(session: Session, *, user: User, settings: Settings) -> Enrolment:
    """A pending secret for a user not yet enrolled (kept until confirmed, so reloading the page
    shows the same)."""
    if user.totp_secret is None:
        begin_write(session)
        user.totp_secret, user.totp_confirmed_at, user.totp_last_step = pyotp.random_base32(), None, None
        session.commit()
    assert user.totp_secret is not None
    uri = pyotp.TOTP(user.totp_secret).provisioning_uri(
        name=user.email, issuer_name=settings.issuing_authority
    )
    qr = segno.make(uri, error="m")
    # A viewBox and no fixed size: the page's CSS scales the whole code, quiet zone included.
    return Enrolment(
        secret=user.totp_secret,
        uri=uri,
        qr_svg=qr.svg_inline(scale=4, omitsize=True, title=gettext("Enrolment QR code")),
    )


def _step_of(secret: str, code: str, now: float) -> int | None:
    """The time step whose code this is, within the allowed drift, or None."""
    totp, current = pyotp.TOTP(secret), int(now // STEP_SECONDS)
    for step in range(current - DRIFT_STEPS, current + DRIFT_STEPS + 1):
        if secrets.compare_digest(totp.at(step * STEP_SECONDS), code):
            return step
    return None


def _take_step(session: Session, user: User, step: int) -> bool:
    """Record the step as used, unless this or a later one was used already (one atomic UPDATE)."""
    begin_write(session)
    taken = session.execute(
        update(User)
        .where(User.id == user.id, or_(User.totp_last_step.is_(None), User.totp_last_step < step))
        .values(totp_last_step=step)
        .execution_options(synchronize_session=False)
    )
    session.commit()
    session.refresh(user)
    return bool(getattr(taken, "rowcount", 0))


def _claim(session: Session, user: User, settings: Settings, key: str | None = None) -> throttle.ClaimedCheck:
    check = throttle.claim_key(
        session, key=key or f"code:{user.id}", limit=settings.login_max_failures, settings=settings
    )
    if isinstance(check, throttle.LockedOut):
        raise CodeRefused(
            f"code: too many wrong codes; wait {check.wait_minutes} minutes, then try again",
            field="code",
            rule="lock_out",
        )
    return check


def _wrong() -> CodeRefused:
    return CodeRefused(
        "code: that code is not right or was used already; enter the 6-digit code your app shows now",
        field="code",
        rule="totp",
    )


def _normalised(code: str) -> str:
    return "".join(code.split()).replace("-", "").upper()


def confirm_enrolment(session: Session, *, user: User, code: str, settings: Settings) -> list[str]:
    """Make the pending secret the account's second factor once a code from it is right; return the
    new recovery codes, in text this once (only their hashes are kept)."""
    check = _claim(session, user, settings)
    step = _step_of(user.totp_secret or "", _normalised(code), time.time()) if user.totp_secret else None
    if step is None or not _take_step(session, user, step):
        throttle.settle_check(session, check, outcome=throttle.BAD_CREDENTIALS)
        raise _wrong()
    throttle.settle_check(session, check, outcome=throttle.SUCCESS)
    begin_write(session)
    user.totp_confirmed_at = utcnow()
    session.execute(delete(RecoveryCode).where(RecoveryCode.user_id == user.id))
    codes = [_recovery_code() for _ in range(RECOVERY_CODES)]
    session.add_all(RecoveryCode(user_id=user.id, code_hash=_hash(code)) for code in codes)
    session.commit()
    return codes


def check_code(
    session: Session, *, user: User, code: str, settings: Settings, throttle_key: str | None = None
) -> str:
    """Accept a current code or an unused recovery code, once; return which ("code" or
    "recovery code"), or raise CodeRefused. Wrong codes count against `throttle_key` (a signed-in
    session's own, for re-authentication), else against the account's codes."""
    check = _claim(session, user, settings, throttle_key)
    typed = _normalised(code)
    step = _step_of(user.totp_secret or "", typed, time.time()) if is_enrolled(user) else None
    if step is not None and _take_step(session, user, step):
        kind = "code"
    elif len(typed) == 16 and _use_recovery_code(session, user, typed):
        kind = "recovery code"
        begin_write(session)
        left = remaining_recovery_codes(session, user=user)
        record_event(
            session,
            action="user.recovery_code_used",
            target_type="user",
            target_id=user.id,
            details={"left": left},
        )
        session.commit()
    else:
        throttle.settle_check(session, check, outcome=throttle.BAD_CREDENTIALS)
        raise _wrong()
    throttle.settle_check(session, check, outcome=throttle.SUCCESS)
    return kind


def mark_passed(session: Session, record: UserSession) -> None:
    """This browser session has passed the second factor now."""
    begin_write(session)
    record.second_factor_at = record.verified_at = utcnow()
    session.commit()


def reset_second_factor(session: Session, *, user: User) -> None:
    """Remove the account's second factor and recovery codes: it enrols again at its next sign-in."""
    begin_write(session)
    user.totp_secret, user.totp_confirmed_at, user.totp_last_step = None, None, None
    session.execute(delete(RecoveryCode).where(RecoveryCode.user_id == user.id))
    session.execute(update(UserSession).where(UserSession.user_id == user.id).values(second_factor_at=None))
    session.commit()


def remaining_recovery_codes(session: Session, *, user: User) -> int:
    """How many of the account's recovery codes are still unused."""
    query = select(func.count()).where(RecoveryCode.user_id == user.id, RecoveryCode.used_at.is_(None))
    return int(session.scalar(query) or 0)


def _recovery_code() -> str:
    alphabet = "ABCDEFGHJKLMNPQRSTUVWXYZ23456789"  # no 0/O, 1/I: read off paper
    raw = "".join(secrets.choice(alphabet) for _ in range(16))
    return "-".join(raw[i : i + 4] for i in range(0, 16, 4))


def _hash(code: str) -> str:
    return hashlib.sha256(_normalised(code).encode()).hexdigest()


def _use_recovery_code(session: Session, user: User, typed: str) -> bool:
    begin_write(session)
    used = session.execute(
        update(RecoveryCode)
        .where(
            RecoveryCode.user_id == user.id,
            RecoveryCode.code_hash == _hash(typed),
            RecoveryCode.used_at.is_(None),
        )
        .values(used_at=utcnow())
        .execution_options(synchronize_session=False)
    )
    session.commit()
    return bool(getattr(used, "rowcount", 0))
