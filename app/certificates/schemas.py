"""API shapes of certificates."""

from __future__ import annotations

from datetime import date, datetime
from typing import Literal

from pydantic import BaseModel, Field

EXAMPLE_NUMBER = "TRK-2026-000001-A"


class RevocationOut(BaseModel):
    """When and why a certificate was revoked."""

    revoked_at: datetime
    reason: str


class IssuerOut(BaseModel):
    """Who issued the document: a role and a name to show (never an email address)."""

    role: Literal["station", "officer", "administrator"]
    name: str = Field(examples=["Inspection officer"])


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
    issued_by: IssuerOut
    supersedes: str | None = Field(description="The number of the certificate this one replaced.")
    superseded_by: str | None
    revocation: RevocationOut | None
    key_id: str
    qr_payload: str = Field(
        description="The signed payload: a CWT (RFC 8392) in a COSE_Sign1 signed with EdDSA (Ed25519), "
        "in base45 (RFC 9285); certificates issued before 2026-12 carry a JWS compact token instead. "
        "Keys at /.well-known/trikecert-keys.json."
    )
    verify_url: str
    qr_url: str = Field(
        description="What the QR code encodes: <BASE_URL in capitals>/V/<qr_payload, percent-escaped> "
        "(for a JWS: verify_url with ?p=<qr_payload>)."
    )
    pdf_url: str
    pdf_sha256: str


class VerificationOut(BaseModel):
    """A public check of a document: only what its paper prints, and whether a scanned QR code is genuine."""

    number: str = Field(examples=[EXAMPLE_NUMBER])
    kind: Literal["certificate", "refusal"]
    status: Literal["valid", "revoked", "expired", "superseded"] = Field(
        description="Now: valid (in force), revoked, expired or superseded (by `superseded_by`). "
        "A refusal that is valid is in force: the vehicle may carry only `max_compliant_occupants`."
    )
    registration_number: str
    max_compliant_occupants: int = Field(
        description="Occupants the vehicle is certified to carry, the driver counted (0: none)."
    )
    issued_on: date
    valid_until: date = Field(description="The last day shown on the paper, in the service's time zone.")
    superseded_by: str | None = Field(
        default=None, description="Only when superseded: the number of the newer document."
    )
    qr: Literal["genuine", "not_genuine"] | None = Field(
        default=None, description="Only with `p`: whether the scanned payload is genuine for this record."
    )
    reason: (
        Literal["ok", "malformed", "unsupported_algorithm", "unknown_key", "bad_signature", "tampered"] | None
    ) = Field(default=None, description="Only with `p`: ok, or why the payload is not genuine.")
    reason_text: str | None = Field(default=None, description="Only with `p`: the reason in words.")
