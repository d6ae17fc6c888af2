"""API shapes of certificates."""

from __future__ import annotations

from datetime import date, datetime
from typing import Literal

from pydantic import BaseModel, Field

EXAMPLE_NUMBER = "TRK-2026-000001-E"


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
        description="The record's state, computed now: revoked, superseded, expired (past `expires_at`) "
        "or issued. A refusal is issued too: read `document_status` or `in_force` to know what the paper "
        "means."
    )
    document_status: Literal["certified", "refused", "revoked", "superseded", "expired"] = Field(
        description="What the paper means now, as the public verification says it: certified (a "
        "certificate in force), refused (a refusal that stands), revoked, superseded or expired."
    )
    in_force: bool = Field(description="True only for a certificate that certifies the vehicle now.")
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


QrReason = Literal[
    "ok", "malformed", "unsupported_algorithm", "unknown_key", "withdrawn_key", "bad_signature", "tampered"
]


class VerificationOut(BaseModel):
    """A public check of a document: only what its paper prints, what it means now, and whether a
    scanned QR code is genuine. Read `status` (or `in_force`): only `certified` certifies the vehicle."""

    number: str = Field(examples=[EXAMPLE_NUMBER])
    kind: Literal["certificate", "refusal"] = Field(
        description="certificate: the vehicle passed; refusal: it failed, and the paper says what it "
        "may carry."
    )
    status: Literal["certified", "refused", "revoked", "superseded", "expired"] = Field(
        description="What the document means now. certified: a certificate in force, the vehicle is "
        "certified for `max_compliant_occupants`. refused: a refusal in force, the vehicle is NOT "
        "certified. revoked (`revoked_on`, `reason`), superseded (by `superseded_by`) and expired: the "
        "document no longer counts, whatever its kind. (Until 2026-12 a document in force was `valid`, "
        "for a refusal too: that value is gone.)"
    )
    in_force: bool = Field(
        description="True only when `status` is certified: this paper certifies the vehicle now. False "
        "for a refusal (it certifies nothing, even while it stands) and for anything revoked, "
        "superseded or expired."
    )
    registration_number: str
    max_compliant_occupants: int = Field(
        description="Occupants the vehicle may carry, the DRIVER COUNTED: 1 is the driver alone, 3 the "
        "driver and 2 passengers, 0 nobody (the vehicle must not be used). For a refusal it is what "
        "the vehicle may carry at most, not a certification."
    )
    issued_on: date
    valid_until: date = Field(
        description="The last day the paper names (for a refusal: until when it stands), in the "
        "service's time zone. After it the status is expired."
    )
    revoked_on: date | None = Field(
        default=None, description="Only when revoked: the day it was revoked, in the service's time zone."
    )
    reason: str | None = Field(
        default=None,
        description="Only when revoked: why, as the authority recorded it (shown to anyone who checks).",
    )
    superseded_by: str | None = Field(
        default=None, description="Only when superseded: the number of the newer document; verify it too."
    )
    superseded_on: date | None = Field(
        default=None, description="Only when superseded: the day the newer document was issued."
    )
    qr: Literal["genuine", "not_genuine"] | None = Field(
        default=None,
        description="Only with `p`: whether the scanned payload is genuine for this record. A genuine code "
        "on a document that is not in force is still not a certificate: read `status`.",
    )
    qr_reason: QrReason | None = Field(
        default=None, description="Only with `p`: ok, or why the payload is not genuine."
    )
    qr_reason_text: str | None = Field(default=None, description="Only with `p`: `qr_reason` in words.")
