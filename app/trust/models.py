"""The signing keys' table: the public half of every key that ever signed, its source and period."""

from __future__ import annotations

from datetime import datetime
from typing import Any

from sqlalchemy import JSON, Boolean, CheckConstraint, String
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
