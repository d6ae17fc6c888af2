"""Check a scanned QR payload against the published keys and, when known, the stored certificate;
the public JSON verification of a document."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

from app.certificates.models import Certificate
from app.certificates.records import certificate_status
from app.certificates.schemas import VerificationOut
from app.certificates.wording import in_force, public_kind, public_status
from app.trust.claims import Claims, PayloadRefused, Verified
from app.trust.signing import verify_input
from app.trust.validity import local_date
from app.wording import verdict_mark


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


def verification_of(certificate: Certificate, payload: PayloadCheck | None = None) -> VerificationOut:
    """The public JSON verification: the facts the paper prints, what it means now, and the QR check."""
    status = public_status(certificate.kind, certificate_status(certificate))
    revocation = certificate.revocation if status == "revoked" else None
    newer = certificate.superseded_by if status == "superseded" else None
    return VerificationOut.model_validate(
        {
            "number": certificate.number,
            "kind": public_kind(certificate.kind),
            "status": status,
            "in_force": in_force(status),
            "registration_number": certificate.registration_number,
            "max_compliant_occupants": certificate.max_compliant_occupants,
            "issued_on": local_date(certificate.issued_at),
            "valid_until": local_date(certificate.expires_at),
            "revoked_on": local_date(revocation.revoked_at) if revocation is not None else None,
            "reason": revocation.reason if revocation is not None else None,
            "superseded_by": newer.number if newer is not None else None,
            "superseded_on": local_date(newer.issued_at) if newer is not None else None,
            "qr": None if payload is None else ("genuine" if payload.genuine else "not_genuine"),
            "qr_reason": None if payload is None else payload.reason,
            "qr_reason_text": None if payload is None else payload.message,
        }
    )
