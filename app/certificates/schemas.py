"""API shapes of certificates."""

from __future__ import annotations

from datetime import datetime
from typing import Literal

from pydantic import BaseModel, Field

EXAMPLE_NUMBER = "TRK-2026-000001-A"


class RevocationOut(BaseModel):
    """When and why a certificate was revoked."""

    revoked_at: datetime
    reason: str


class CertificateOut(BaseModel):
    """An issued certificate (or refusal) with its current status and signed QR payload."""

    number: str = Field(examples=[EXAMPLE_NUMBER])
    kind: Literal["compliant", "refusal"]
    status: Literal["issued", "revoked", "superseded", "expired"] = Field(
        description="Computed now: revoked, superseded, expired (past `expires_at`) or issued."
    )
    registration_number: str
    inspection_id: int
    compliant: bool
    max_compliant_occupants: int
    max_occupancy: str = Field(
        description="The occupancy sentence, as on the page and the PDF, e.g. 'Certified for the driver "
        "and up to 2 passengers' or 'This vehicle must not carry passengers'."
    )
    verdict: str
    issued_at: datetime
    expires_at: datetime
    issued_by: str
    supersedes: str | None = Field(description="The number of the certificate this one replaced.")
    superseded_by: str | None
    revocation: RevocationOut | None
    key_id: str
    qr_payload: str = Field(
        description="JWS compact, signed with Ed25519; keys at /.well-known/trikecert-keys.json."
    )
    verify_url: str
    qr_url: str = Field(description="What the QR code encodes: verify_url with ?p=<qr_payload>.")
    pdf_url: str
    pdf_sha256: str
