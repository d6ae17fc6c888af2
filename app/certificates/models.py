"""Certificate tables: the certificate itself, its revocation, the audit log, the yearly counter.

A certificate row, a revocation row and an audit row are written once and never changed or
deleted (guard.py in the code, triggers in the database). Revocation is a row of its own;
supersession is the `supersedes_id` of the newer certificate; so nothing certified is updated.
"""

from __future__ import annotations

from datetime import datetime
from typing import Any

from sqlalchemy import (
    JSON,
    Boolean,
    CheckConstraint,
    ForeignKey,
    Integer,
    LargeBinary,
    String,
    Text,
    UniqueConstraint,
)
from sqlalchemy.orm import Mapped, mapped_column, relationship

import app.trust.models  # noqa: F401  (certificate.key_id refers to its signing_key table)
from app.db import Base, UTCDateTime, utcnow

KINDS = ("compliant", "refusal")
AUDIT_ACTIONS = ("issue", "reissue", "supersede", "revoke")


class CertificateSequence(Base):
    """The last certificate sequence number handed out in a year (one row per year)."""

    __tablename__ = "certificate_sequence"

    year: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=False)
    last_value: Mapped[int] = mapped_column(Integer)


class Certificate(Base):
    """One issued certificate (or refusal): its number, dates, signed payload, facts and PDF, frozen."""

    __tablename__ = "certificate"
    __table_args__ = (
        UniqueConstraint("year", "sequence"),
        CheckConstraint("kind IN ('compliant', 'refusal')", name="kind"),
        CheckConstraint("expires_at > issued_at", name="expiry_after_issue"),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    number: Mapped[str] = mapped_column(String(24), unique=True)
    year: Mapped[int] = mapped_column(Integer)
    sequence: Mapped[int] = mapped_column(Integer)
    kind: Mapped[str] = mapped_column(String(16))
    inspection_id: Mapped[int] = mapped_column(ForeignKey("inspection.id"), index=True)
    vehicle_id: Mapped[int] = mapped_column(ForeignKey("vehicle.id"), index=True)
    registration_number: Mapped[str] = mapped_column(String(32))
    compliant: Mapped[bool] = mapped_column(Boolean)
    max_compliant_occupants: Mapped[int] = mapped_column(Integer)
    issued_at: Mapped[datetime] = mapped_column(UTCDateTime(), index=True)
    expires_at: Mapped[datetime] = mapped_column(UTCDateTime())
    issued_by: Mapped[str] = mapped_column(
        String(200)
    )  # who, as in the audit log: station:3, user:5, cli:root
    issued_by_station_id: Mapped[int | None] = mapped_column(ForeignKey("station.id"))
    issued_by_user_id: Mapped[int | None] = mapped_column(ForeignKey("user_account.id"))
    supersedes_id: Mapped[int | None] = mapped_column(ForeignKey("certificate.id"), unique=True)
    # What was certified, as printed: vehicle, inspection, readings, Table 4, verdict (see facts.py).
    facts: Mapped[dict[str, Any]] = mapped_column(JSON)
    key_id: Mapped[str] = mapped_column(ForeignKey("signing_key.kid"))
    qr_payload: Mapped[str] = mapped_column(Text)
    pdf: Mapped[bytes] = mapped_column(LargeBinary, deferred=True)
    pdf_sha256: Mapped[str] = mapped_column(String(64))
    # The language printed under the English (ha, yo, ig, pcm), or None for English only: kept so
    # the paper is worded in the same languages whenever it is rendered or stamped again.
    second_language: Mapped[str | None] = mapped_column(String(8), default=None)

    revocation: Mapped[CertificateRevocation | None] = relationship(
        lazy="selectin", back_populates="certificate"
    )
    supersedes: Mapped[Certificate | None] = relationship(
        remote_side=[id], foreign_keys=[supersedes_id], back_populates="superseded_by", lazy="selectin"
    )
    superseded_by: Mapped[Certificate | None] = relationship(
        foreign_keys=[supersedes_id], back_populates="supersedes", uselist=False, lazy="selectin"
    )


class CertificateRevocation(Base):
    """The revocation of one certificate: when, by whom and why (at most one per certificate)."""

    __tablename__ = "certificate_revocation"
    __table_args__ = (CheckConstraint("length(trim(reason)) > 0", name="reason_given"),)

    certificate_id: Mapped[int] = mapped_column(ForeignKey("certificate.id"), primary_key=True)
    revoked_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    revoked_by: Mapped[str] = mapped_column(String(200))
    reason: Mapped[str] = mapped_column(Text)

    certificate: Mapped[Certificate] = relationship(back_populates="revocation")


class CertificateAudit(Base):
    """One entry of the audit log: who did what to which certificate, when and why."""

    __tablename__ = "certificate_audit"
    __table_args__ = (
        CheckConstraint("action IN ('issue', 'reissue', 'supersede', 'revoke')", name="action"),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    certificate_id: Mapped[int] = mapped_column(ForeignKey("certificate.id"), index=True)
    action: Mapped[str] = mapped_column(String(16))
    actor: Mapped[str] = mapped_column(String(200))
    at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    reason: Mapped[str | None] = mapped_column(Text)
