"""Read certificates: find them by number, their computed status, frozen facts and stored PDF."""

from __future__ import annotations

from datetime import datetime
from typing import Literal

from sqlalchemy import select
from sqlalchemy.orm import Session

from app.certificates.facts import Facts
from app.certificates.models import Certificate, CertificateAudit
from app.certificates.wording import not_on_record
from app.config import Settings
from app.db import utcnow
from app.errors import NotFound
from app.trust.numbers import InvalidNumber, parse_number

Status = Literal["issued", "revoked", "superseded", "expired"]


def certificate_status(certificate: Certificate, now: datetime | None = None) -> Status:
    """revoked, superseded, expired (computed from the date) or issued, in that order of precedence."""
    if certificate.revocation is not None:
        return "revoked"
    if certificate.superseded_by is not None:
        return "superseded"
    if (now or utcnow()) >= certificate.expires_at:
        return "expired"
    return "issued"


def certificate_facts(certificate: Certificate) -> Facts:
    """The frozen facts a certificate states."""
    return Facts.from_json(certificate.facts)


def verify_base(settings: Settings) -> str:
    """The public verify address without a number: <base_url>/verify."""
    return f"{settings.base_url.rstrip('/')}/verify"


def find_certificate(session: Session, number: str) -> Certificate | None:
    """The certificate with this number (written in any accepted form), or None."""
    try:
        canonical = str(parse_number(number))
    except InvalidNumber:
        return None
    return session.scalar(select(Certificate).where(Certificate.number == canonical))


def get_certificate(session: Session, number: str) -> Certificate:
    """The certificate with this number, or NotFound: rule `format`, `check_letter` or `exists`, in the
    words the verify page and its form give too."""
    try:
        canonical = str(parse_number(number))
    except InvalidNumber as error:
        raise NotFound(f"number: {error}", field="number", rule=error.rule) from error
    certificate = session.scalar(select(Certificate).where(Certificate.number == canonical))
    if certificate is None:
        raise NotFound(f"number: {not_on_record(canonical)}", field="number", rule="exists")
    return certificate


def certificate_pdf(session: Session, certificate: Certificate) -> bytes:
    """The stored PDF bytes, exactly as rendered at issue."""
    pdf = session.scalar(select(Certificate.pdf).where(Certificate.id == certificate.id))
    assert pdf is not None
    return bytes(pdf)


def audit_log(session: Session, certificate: Certificate) -> list[CertificateAudit]:
    """Every audit entry about a certificate, oldest first."""
    query = select(CertificateAudit).where(CertificateAudit.certificate_id == certificate.id)
    return list(session.scalars(query.order_by(CertificateAudit.id)))


def certificates_of_inspection(session: Session, inspection_id: int) -> list[tuple[Certificate, Status]]:
    """The certificates issued from one inspection, oldest first, each with its status now."""
    found = session.scalars(
        select(Certificate).where(Certificate.inspection_id == inspection_id).order_by(Certificate.id)
    ).all()
    return [(certificate, certificate_status(certificate)) for certificate in found]
