"""Accounts, their browser sessions and the log of sign-in attempts."""

from __future__ import annotations

from datetime import datetime

from sqlalchemy import Boolean, CheckConstraint, ForeignKey, Index, String
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
