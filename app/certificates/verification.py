"""Check a scanned QR payload against the published keys and, when known, the stored certificate;
the public JSON verification of a document."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

from app.certificates.claims import Claims, PayloadRefused, Verified
from app.certificates.models import Certificate
from app.certificates.records import certificate_status
from app.certificates.schemas import VerificationOut
from app.certificates.signing import verify_input
from app.certificates.validity import local_date
from app.inspections.wording import verdict_mark


@dataclass(frozen=True)
class PayloadCheck:
    """The outcome of checking a payload: genuine or not, and why, in words."""

    genuine: bool
    reason: str
    message: str
    claims: Claims | None = None
    kid: str | None = None


def expected_claims(certificate: Certificate) -> Claims:
    """The claims a genuine payload of this certificate carries."""
    return Claims(
        number=certificate.number,
        registration=certificate.registration_number,
        issued=local_date(certificate.issued_at),
        expires=local_date(certificate.expires_at),
        verdict=verdict_mark(certificate.compliant),
        max_occupants=certificate.max_compliant_occupants,
    )


def _matches(verified: Verified, certificate: Certificate) -> bool:
    """The signed claims are the record's; a CWT's exact moments too (to the second)."""
    claims = verified.claims
    if claims != expected_claims(certificate):
        return False
    if verified.format == "jws":
        return True
    signed = (claims.issued_at, claims.expires_at)
    return signed == tuple(_second(moment) for moment in (certificate.issued_at, certificate.expires_at))


def _second(moment: datetime) -> datetime:
    return datetime.fromtimestamp(int(moment.timestamp()), UTC)


def check_payload(text: str, jwks: dict[str, Any], certificate: Certificate | None = None) -> PayloadCheck:
    """Verify a token or verify URL; with a certificate, its signed claims must also match the record."""
    try:
        verified = verify_input(text, jwks)
    except PayloadRefused as refused:
        return PayloadCheck(genuine=False, reason=refused.reason, message=refused.message)
    if certificate is not None and not _matches(verified, certificate):
        return PayloadCheck(
            genuine=False,
            reason="tampered",
            message=f"tampered content: the signed payload is for {verified.claims.number} "
            f"({verified.claims.registration}) and does not match the record of {certificate.number}",
            claims=verified.claims,
            kid=verified.kid,
        )
    return PayloadCheck(
        genuine=True,
        reason="ok",
        message=f"the signature checks out (key {verified.kid})",
        claims=verified.claims,
        kid=verified.kid,
    )


PUBLIC_STATUS = {"issued": "valid", "revoked": "revoked", "expired": "expired", "superseded": "superseded"}


def verification_of(certificate: Certificate, payload: PayloadCheck | None = None) -> VerificationOut:
    """The public JSON verification: the facts the paper prints, its status now, and the QR check."""
    status = certificate_status(certificate)
    superseded_by = certificate.superseded_by
    return VerificationOut.model_validate(
        {
            "number": certificate.number,
            "kind": "certificate" if certificate.kind == "compliant" else "refusal",
            "status": PUBLIC_STATUS[status],
            "registration_number": certificate.registration_number,
            "max_compliant_occupants": certificate.max_compliant_occupants,
            "issued_on": local_date(certificate.issued_at),
            "valid_until": local_date(certificate.expires_at),
            "superseded_by": superseded_by.number if superseded_by is not None else None,
            "qr": None if payload is None else ("genuine" if payload.genuine else "not_genuine"),
            "reason": None if payload is None else payload.reason,
            "reason_text": None if payload is None else payload.message,
        }
    )
