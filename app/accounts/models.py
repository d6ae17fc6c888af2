"""Accounts, their browser sessions and the log of sign-in attempts."""

from __future__ import annotations

from datetime import datetime

from sqlalchemy import BigInteger, Boolean, CheckConstraint, ForeignKey, Index, Integer, String
from sqlalchemy.orm import Mapped, mapped_column, relationship

from app.db import Base, UTCDateTime, utcnow


class User(Base):
    """A person who signs in: an officer inspects, an admin also manages users and stations."""

    __tablename__ = "user_account"
    __table_args__ = (CheckConstraint("role IN ('officer', 'admin')", name="role"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    email: Mapped[str] = mapped_column(String(254), unique=True)
    password_hash: Mapped[str] = mapped_column(String(255))
    role: Mapped[str] = mapped_column(String(16))
    active: Mapped[bool] = mapped_column(Boolean, default=True)
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    # The second factor (RFC 6238 TOTP): a secret is pending until a code confirms it; the last time
    # step a code was accepted for, so that no code is accepted twice.
    totp_secret: Mapped[str | None] = mapped_column(String(64))
    totp_confirmed_at: Mapped[datetime | None] = mapped_column(UTCDateTime())
    totp_last_step: Mapped[int | None] = mapped_column(BigInteger)
    # How documents and pages name the person (None only for accounts made before names were kept).
    display_name: Mapped[str | None] = mapped_column(String(100))
    badge_number: Mapped[str | None] = mapped_column(String(32))

    def shown_as(self) -> str:
        """The person as documents name them, never by email: 'Amina Bello (badge 4471)'."""
        role = "administrator" if self.role == "admin" else "officer"
        name = self.display_name or f"{role} no. {self.id} (no name on record)"
        return f"{name} (badge {self.badge_number})" if self.badge_number else name


class UserSession(Base):
    """A signed-in browser: only the SHA-256 of its cookie is kept, with its CSRF token and timeouts."""

    __tablename__ = "user_session"

    id: Mapped[int] = mapped_column(primary_key=True)
    token_hash: Mapped[str] = mapped_column(String(64), unique=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("user_account.id", ondelete="CASCADE"), index=True)
    csrf_token: Mapped[str] = mapped_column(String(64))
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    last_seen_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    expires_at: Mapped[datetime] = mapped_column(UTCDateTime())
    # One message to show on the next page (after a redirect), then cleared.
    flash: Mapped[str | None] = mapped_column(String(500))
    # When this session last passed the second factor (None: not yet, or not needed).
    second_factor_at: Mapped[datetime | None] = mapped_column(UTCDateTime())
    # When this session last proved who it is (the password, and the code when one is needed): what
    # cannot be undone asks again when this is older than a few minutes (app/accounts/reauth.py).
    verified_at: Mapped[datetime | None] = mapped_column(UTCDateTime())

    user: Mapped[User] = relationship(lazy="joined")


class LoginAttempt(Base):
    """One sign-in attempt, kept for the lock-out rule and for audit; never the password."""

    __tablename__ = "login_attempt"
    __table_args__ = (
        CheckConstraint(
            "outcome IN ('success', 'bad_credentials', 'locked_out', 'disabled')", name="outcome"
        ),
        Index("ix_login_attempt_email_created_at", "email", "created_at"),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    email: Mapped[str] = mapped_column(String(254))
    user_id: Mapped[int | None] = mapped_column(ForeignKey("user_account.id", ondelete="SET NULL"))
    client_ip: Mapped[str | None] = mapped_column(String(45))
    outcome: Mapped[str] = mapped_column(String(16))
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)


class LoginThrottle(Base):
    """Password checks counted against one sign-in key ("email:..." or "address:..."), one row each.

    A check is counted before the password is verified, by one atomic upsert that also reads the
    count back, so concurrent guesses can never be verified beyond the limit.
    """

    __tablename__ = "login_throttle"

    key: Mapped[str] = mapped_column(String(300), primary_key=True)
    checks: Mapped[int] = mapped_column(Integer)
    # Unix seconds of the last check counted while under the limit: the lock-out runs from there.
    last_counted_at: Mapped[int] = mapped_column(BigInteger)


class RecoveryCode(Base):
    """One single-use recovery code of an account, stored only as its SHA-256 (it has 80 random bits)."""

    __tablename__ = "recovery_code"

    id: Mapped[int] = mapped_column(primary_key=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("user_account.id", ondelete="CASCADE"), index=True)
    code_hash: Mapped[str] = mapped_column(String(64), unique=True)
    used_at: Mapped[datetime | None] = mapped_column(UTCDateTime())
