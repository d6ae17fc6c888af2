"""Create, list, disable and reset officer and admin accounts; passwords are kept only as Argon2 hashes."""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Sequence

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.accounts.sessions import end_user_sessions
from app.errors import Conflict, InvalidInput, NotFound
from app.text import checked

ROLES = ("officer", "admin")
MIN_PASSWORD_LENGTH = 10
MAX_PASSWORD_LENGTH = 1024
EMAIL_LENGTH = 254
_EMAIL = re.compile(r"^[^@\s]+@[^@\s]+\.[^@\s]+$")
MAX_NAME_LENGTH = 100
MAX_BADGE_LENGTH = 32
_BADGE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9 ./-]*$")
_hasher = PasswordHasher()


def hash_password(password: str) -> str:
    """An Argon2id hash of the password."""
    return _hasher.hash(password)


def verify_password(password_hash: str, password: str) -> bool:
    """True when the password matches the stored hash."""
    try:
        return _hasher.verify(password_hash, password)
    except (VerificationError, InvalidHashError):
        return False


def normalise_email(email: str) -> str:
    """Emails are matched case-insensitively (and in NFC); InvalidInput when it breaks the text rule."""
    return checked("email", email, max_length=EMAIL_LENGTH, required=False).lower()


def check_password_rules(password: str) -> None:
    """Refuse a password that is too short or too long, or holds a character the text rule refuses."""
    checked("password", password, max_length=MAX_PASSWORD_LENGTH, strip=False)
    if len(password) < MIN_PASSWORD_LENGTH:
        raise InvalidInput(
            f"password: use at least {MIN_PASSWORD_LENGTH} characters", field="password", rule="min_length"
        )


def display_name(value: str) -> str:
    """The person's name as documents print it: NFC, single spaces; refused empty, too long or unprintable."""
    name = " ".join(unicodedata.normalize("NFC", value).split())
    if not name:
        raise InvalidInput(
            "name: enter the person's name as certificates should print it", field="name", rule="required"
        )
    if len(name) > MAX_NAME_LENGTH:
        raise InvalidInput(
            f"name: keep the name to {MAX_NAME_LENGTH} characters (it has {len(name)})",
            field="name",
            rule="max_length",
        )
    if any(unicodedata.category(character) in ("Cc", "Cf", "Cs", "Co", "Cn") for character in name):
        raise InvalidInput(
            "name: use letters, spaces and punctuation only (no control or invisible characters)",
            field="name",
            rule="characters",
        )
    return name


def badge_number(value: str | None) -> str | None:
    """An officer's badge number (optional): letters, digits, spaces, '.', '/', '-', up to 32 characters."""
    badge = " ".join((value or "").split())
    if not badge:
        return None
    if len(badge) > MAX_BADGE_LENGTH or not _BADGE.match(badge):
        raise InvalidInput(
            f"badge: use up to {MAX_BADGE_LENGTH} letters, digits, spaces, '.', '/' or '-', like NSCDC/4471",
            field="badge",
            rule="format",
        )
    return badge


def create_user(
    session: Session,
    *,
    email: str,
    password: str,
    role: str,
    name: str | None = None,
    badge: str | None = None,
) -> User:
    """Store a new account; the email must be new and the role officer or admin.

    The pages and the command line always give a name; None is only for callers that predate names.
    """
    email = normalise_email(email)
    if not _EMAIL.match(email):
        raise InvalidInput(
            "email: enter an email address like name@example.org", field="email", rule="format"
        )
    if role not in ROLES:
        raise InvalidInput("role: choose officer or admin", field="role", rule="choice")
    shown = display_name(name) if name is not None else None
    badge = badge_number(badge)
    check_password_rules(password)
    if session.scalar(select(User.id).where(func.lower(User.email) == email)) is not None:
        raise Conflict(f"email: an account for {email} already exists", field="email", rule="unique")
    user = User(
        email=email, password_hash=hash_password(password), role=role, display_name=shown, badge_number=badge
    )
    session.add(user)
    session.commit()
    return user


def set_user_details(session: Session, *, user: User, name: str, badge: str | None) -> User:
    """Change the name and badge number an account is shown by (documents already issued keep theirs)."""
    user.display_name = display_name(name)
    user.badge_number = badge_number(badge)
    session.commit()
    return user


def list_users(session: Session) -> Sequence[User]:
    """Every account, administrators first, then by email."""
    return session.scalars(select(User).order_by(User.role, User.email)).all()


def get_user(session: Session, user_id: int) -> User:
    """The account with this id, or NotFound."""
    user = session.get(User, user_id)
    if user is None:
        raise NotFound(f"user {user_id} does not exist", field="id", rule="exists")
    return user


def set_user_active(session: Session, *, user: User, active: bool) -> User:
    """Enable or disable an account; disabling ends every session it has."""
    user.active = active
    session.commit()
    if not active:
        end_user_sessions(session, user_id=user.id)
    return user


def set_password(session: Session, *, user: User, password: str, keep_session_id: int | None = None) -> User:
    """Give an account a new password and end its other sessions."""
    check_password_rules(password)
    user.password_hash = hash_password(password)
    session.commit()
    end_user_sessions(session, user_id=user.id, keep_id=keep_session_id)
    return user
