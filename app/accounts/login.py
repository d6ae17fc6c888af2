"""Sign in: count the check against the lock-out, verify the password and the account, log the attempt,
start a session."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.accounts import throttle
from app.accounts.models import User
from app.accounts.service import hash_password, normalise_email, verify_password
from app.accounts.sessions import NewSession, start_session
from app.config import Settings


@cache
def unknown_email_hash() -> str:
    """What a password is verified against when the email is unknown, so a wrong email costs as long
    as a wrong password."""
    # Made at the first such sign-in, not at import: a hash at production cost would be paid by every
    # process that starts (each worker, each command), most of which never sign anyone in.
    return hash_password("not a real password, only for timing")


@dataclass(frozen=True)
class SignInResult:
    """The outcome of a sign-in: a new session, or the reason it was refused."""

    started: NewSession | None
    outcome: str
    locked: throttle.LockedOut | None = None  # who must wait, and how long, when locked out


def sign_in(
    session: Session, *, email: str, password: str, client_ip: str | None, settings: Settings
) -> SignInResult:
    """Start a session when the credentials are right, the account active and not locked out."""
    email = normalise_email(email)
    check = throttle.claim_check(session, email=email, client_ip=client_ip, settings=settings)
    if isinstance(check, throttle.LockedOut):
        throttle.record_attempt(
            session, email=email, outcome=throttle.LOCKED_OUT, user_id=None, client_ip=client_ip
        )
        return SignInResult(started=None, outcome=throttle.LOCKED_OUT, locked=check)
    user = session.scalar(select(User).where(func.lower(User.email) == email))
    if user is None:
        verify_password(unknown_email_hash(), password)
        outcome = throttle.BAD_CREDENTIALS
    elif not verify_password(user.password_hash, password):
        outcome = throttle.BAD_CREDENTIALS
    elif not user.active:
        outcome = throttle.DISABLED
    else:
        throttle.settle_check(session, check, outcome=throttle.SUCCESS)
        throttle.record_attempt(
            session, email=email, outcome=throttle.SUCCESS, user_id=user.id, client_ip=client_ip
        )
        return SignInResult(
            started=start_session(session, user=user, settings=settings), outcome=throttle.SUCCESS
        )
    throttle.settle_check(session, check, outcome=outcome)
    throttle.record_attempt(
        session, email=email, outcome=outcome, user_id=user.id if user else None, client_ip=client_ip
    )
    return SignInResult(started=None, outcome=outcome)
