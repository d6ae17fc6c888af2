"""The signing keys' table: the public half of every key that ever signed, its source and period."""

from __future__ import annotations

from datetime import datetime
from typing import Any

from sqlalchemy import JSON, BigInteger, Boolean, CheckConstraint, ForeignKey, String, Text, UniqueConstraint
from sqlalchemy.orm import Mapped, mapped_column

from app.db import Base, UTCDateTime, utcnow

KEY_SOURCES = ("database", "configuration", "file", "pkcs11")


class SigningKey(Base):
    """The public half of an Ed25519 key that signs QR payloads and audit checkpoints; kept for good so
    old certificates stay verifiable. The private half is held outside the database (keys.py)."""

    __tablename__ = "signing_key"
    __table_args__ = (CheckConstraint(f"source IN {KEY_SOURCES!r}", name="source"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    kid: Mapped[str] = mapped_column(String(32), unique=True)
    public_jwk: Mapped[dict[str, Any]] = mapped_column(JSON)
    # Where the private key is held (never here): "file", "pkcs11", "configuration"; "database" for a
    # key made while keys were kept in the database (moved out or destroyed by c27a1e000001).
    source: Mapped[str] = mapped_column(String(16))
    # active_history: the stored values are loaded before a change, so certificates/guard.py sees a revival.
    active: Mapped[bool] = mapped_column(Boolean, default=True, active_history=True)
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    retired_at: Mapped[datetime | None] = mapped_column(UTCDateTime(), active_history=True)


class KeyEndorsement(Base):
    """A statement signed by one key about another (docs/verification.md, "The chain of keys"): at a
    rotation the old key names the new one its `successor` and the new key names the old one its
    `predecessor`; the keys on record when the endorsements began are vouched for the same way by the
    key in force then (`predecessor`, listed in key_grandfathered). Written once, never changed."""

    __tablename__ = "key_endorsement"
    __table_args__ = (
        CheckConstraint("relation IN ('successor', 'predecessor')", name="relation"),
        UniqueConstraint("signer_kid", "subject_kid", "relation"),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    signer_kid: Mapped[str] = mapped_column(ForeignKey("signing_key.kid"))
    subject_kid: Mapped[str] = mapped_column(ForeignKey("signing_key.kid"), index=True)
    relation: Mapped[str] = mapped_column(String(16))
    at: Mapped[int] = mapped_column(BigInteger)  # NumericDate, as signed
    signature: Mapped[str] = mapped_column(String(128))  # base64url Ed25519 over endorsement_text()
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)


class KeyWithdrawal(Base):
    """A key withdrawn because it may be in other hands, signed by the key in force (never the key
    itself): its papers no longer count as genuine online and show "Cannot confirm" offline."""

    __tablename__ = "key_withdrawal"
    __table_args__ = (CheckConstraint("length(trim(reason)) > 0", name="reason_given"),)

    kid: Mapped[str] = mapped_column(ForeignKey("signing_key.kid"), primary_key=True)
    signer_kid: Mapped[str] = mapped_column(ForeignKey("signing_key.kid"))
    at: Mapped[int] = mapped_column(BigInteger)
    reason: Mapped[str] = mapped_column(Text)
    withdrawn_by: Mapped[str] = mapped_column(String(200))
    signature: Mapped[str] = mapped_column(String(128))


class KeyGrandfathered(Base):
    """The keys on record when key endorsements began (filled once by the migration, as the tables'
    owner; the app's role may only read it): the key in force vouches for them on its first start."""

    __tablename__ = "key_grandfathered"

    kid: Mapped[str] = mapped_column(String(32), primary_key=True)
