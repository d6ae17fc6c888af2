"""Check a scanned QR payload against the published keys and, when known, the stored certificate."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from app.certificates.models import Certificate
from app.certificates.signing import Claims, PayloadRefused, verify_input
from app.certificates.validity import local_date


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
        verdict="C" if certificate.compliant else "NC",
        max_occupants=certificate.max_compliant_occupants,
    )


def check_payload(text: str, jwks: dict[str, Any], certificate: Certificate | None = None) -> PayloadCheck:
    """Verify a token or verify URL; with a certificate, its signed claims must also match the record."""
    try:
        verified = verify_input(text, jwks)
    except PayloadRefused as refused:
        return PayloadCheck(genuine=False, reason=refused.reason, message=refused.message)
    if certificate is not None and verified.claims != expected_claims(certificate):
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
