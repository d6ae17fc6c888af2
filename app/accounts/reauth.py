"""Re-authentication before what cannot be undone: the password, and a current code when the account
has a second factor, again, once the session's last check is more than a few minutes old.

Both checks count against the same atomic lock-out as signing in, so a stolen session cookie cannot
be used to guess the password here either. Every confirmation and every refusal is in the audit log.
"""

from __future__ import annotations

from datetime import datetime, timedelta

from sqlalchemy.orm import Session

from app.accounts import second_factor, throttle
from app.accounts.models import UserSession
from app.accounts.service import verify_password
from app.audit.recorder import record_event
from app.config import Settings
from app.db import begin_write, utcnow
from app.errors import ServiceError

FRESH_FOR = timedelta(minutes=5)
PASSWORD_FIELD = "reauth_password"  # noqa: S105 (a form field name)
CODE_FIELD = "reauth_code"


class ReauthenticationRefused(ServiceError):
    """The password or the code given to confirm an action is wrong, or too many were tried (422)."""

    status = 422


def is_fresh(record: UserSession, now: datetime | None = None) -> bool:
    """True when the session proved who it is within the last five minutes."""
    if record.verified_at is None:
        return False
    return (now or utcnow()) - record.verified_at < FRESH_FOR


def needs_code(record: UserSession, settings: Settings) -> bool:
    """True when confirming takes a code from the authenticator app as well as the password."""
    return second_factor.needs_second_factor(record.user, settings)


def _record(session: Session, record: UserSession, action: str, client_ip: str | None) -> None:
    begin_write(session)
    record_event(
        session,
        action=action,
        target_type="user",
        target_id=record.user_id,
        details={"client_ip": client_ip},
    )
    session.commit()


def confirm(
    session: Session,
    *,
    record: UserSession,
    password: str,
    code: str,
    client_ip: str | None,
    settings: Settings,
) -> None:
    """Check the password (and the code when one is needed) and mark the session as just verified;
    raise ReauthenticationRefused, naming the field, when either is wrong."""
    user = record.user
    # Counted against this session alone: wrong sign-ins at the account (an attacker's) never stop
    # an officer who is signed in, and this session's wrong answers lock only itself.
    check = throttle.claim_key(
        session, key=f"reauth:{record.id}", limit=settings.login_max_failures, settings=settings
    )
    if isinstance(check, throttle.LockedOut):
        _record(session, record, "user.reauthentication_locked_out", client_ip)
        raise ReauthenticationRefused(
            f"{PASSWORD_FIELD}: too many wrong passwords; wait {check.wait_minutes} minutes, then try again",
            field=PASSWORD_FIELD,
            rule="lock_out",
        )
    if not verify_password(user.password_hash, password):
        throttle.settle_check(session, check, outcome=throttle.BAD_CREDENTIALS)
        _record(session, record, "user.reauthentication_failed", client_ip)
        raise ReauthenticationRefused(
            f"{PASSWORD_FIELD}: that is not your password", field=PASSWORD_FIELD, rule="password"
        )
    throttle.settle_check(session, check, outcome=throttle.SUCCESS)
    if needs_code(record, settings):
        try:
            second_factor.check_code(
                session, user=user, code=code, settings=settings, throttle_key=f"reauth-code:{record.id}"
            )
        except second_factor.CodeRefused as error:
            _record(session, record, "user.reauthentication_failed", client_ip)
            raise ReauthenticationRefused(
                error.message.replace("code:", f"{CODE_FIELD}:", 1),
                field=CODE_FIELD,
                rule=error.problems[0].rule if error.problems else "totp",
            ) from error
    begin_write(session)
    record.verified_at = utcnow()
    record_event(
        session,
        action="user.reauthenticated",
        target_type="user",
        target_id=record.user_id,
        details={"client_ip": client_ip},
    )
    session.commit()
