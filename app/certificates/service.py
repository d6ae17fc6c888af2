"""Issue, reissue and revoke certificates; every door (API, pages, CLI) calls these.

Issuing allocates the year's next number first: that serialises issuers (sequence.py), so the
rules below are checked against every certificate already committed. A vehicle's certificates
form a chain: each new one supersedes the vehicle's current one (not revoked, not superseded).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from datetime import datetime
from typing import TYPE_CHECKING, Literal

from sqlalchemy import and_, or_, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from app.certificates.actors import Actor, Forbidden
from app.certificates.facts import facts_of
from app.certificates.models import Certificate, CertificateAudit, CertificateRevocation
from app.certificates.records import certificate_status, get_certificate, verify_base
from app.certificates.sequence import allocate_number
from app.config import SECOND_LANGUAGES, Settings
from app.db import utcnow
from app.errors import Conflict, InvalidInput
from app.i18n.active import use_locale
from app.i18n.locales import ENGLISH
from app.inspections.models import Inspection
from app.inspections.service import get_inspection
from app.stations.scale import CalibrationRefused
from app.text import checked
from app.trust.keys import current_signer
from app.trust.numbers import parse_number
from app.trust.signing import Claims, issuer_claim, qr_url_of, sign_payload
from app.trust.validity import add_months, local_date
from app.wording import document_kind, verdict_mark

if TYPE_CHECKING:
    from app.certificates.pdf import CertificateDocument

REASON_LENGTH = 1000


def render_pdf(document: CertificateDocument) -> bytes:
    """The paper's PDF, the PDF library loaded by the first paper a process makes (not by every
    process that starts: each worker, each command)."""
    from app.certificates import pdf

    return pdf.render_pdf(document)


@dataclass(frozen=True)
class Issued:
    """The certificate for an inspection, and whether this call created it."""

    certificate: Certificate
    created: bool


def _current_of_vehicle(session: Session, vehicle_id: int) -> Certificate | None:
    """The vehicle's certificate that is neither revoked nor superseded (at most one), freshly read."""
    newer = select(Certificate.supersedes_id).where(Certificate.supersedes_id.is_not(None))
    query = (
        select(Certificate)
        .where(Certificate.vehicle_id == vehicle_id, Certificate.revocation == None)  # noqa: E711
        .where(Certificate.id.not_in(newer))
        .order_by(Certificate.id.desc())
        .execution_options(populate_existing=True)
    )
    return session.scalars(query).first()


def paper_language(choice: str | None, settings: Settings) -> str | None:
    """The language printed under the English: the one chosen ('en' for English only), else the
    setting's; None for English only. Any other value is refused, naming the field."""
    if choice is None or choice == "":
        choice = settings.paper_second_language
    if choice in ("", ENGLISH):
        return None
    if choice not in SECOND_LANGUAGES:
        raise InvalidInput(
            f"second_language: {choice[:20]!r} is not a paper language; choose en (English only) or one "
            f"of {', '.join(SECOND_LANGUAGES)}",
            field="second_language",
            rule="language",
        )
    return choice


def issue_certificate(
    session: Session,
    *,
    inspection_id: int,
    actor: Actor,
    settings: Settings,
    now: datetime | None = None,
    second_language: str | None = None,
) -> Issued:
    """Certify an inspection (a refusal when it is not compliant); the existing one if already certified.

    A station may certify only its own inspections. A newer certified inspection of the same
    vehicle, or a revoked certificate of this one, is a 409: weigh the vehicle again. The paper is
    printed in English and `second_language` (see paper_language); an existing one stays as issued.
    """
    language = paper_language(second_language, settings)
    now = now or utcnow()
    inspection = get_inspection(session, inspection_id, station_id=actor.station_id)
    number = allocate_number(session, now.year)
    current = _current_of_vehicle(session, inspection.vehicle_id)
    if current is not None and current.inspection_id == inspection.id:
        session.rollback()
        if certificate_status(current, now) == "expired":
            raise Conflict(
                f"inspection_id: {document_kind(current.kind)} {current.number} of this inspection "
                "has expired; weigh the vehicle again",
                field="inspection_id",
                rule="expired",
            )
        return Issued(certificate=current, created=False)
    revoked = session.execute(
        select(Certificate.number, Certificate.kind)
        .where(Certificate.inspection_id == inspection.id, Certificate.revocation != None)  # noqa: E711
        .limit(1)
    ).first()
    if revoked is not None:
        session.rollback()
        raise Conflict(
            f"inspection_id: {document_kind(revoked.kind)} {revoked.number} of this inspection was revoked; "
            "weigh the vehicle again",
            field="inspection_id",
            rule="revoked",
        )
    if current is not None:
        shown = session.get(Inspection, current.inspection_id)
        assert shown is not None
        if (shown.created_at, shown.id) > (inspection.created_at, inspection.id):
            session.rollback()
            raise Conflict(
                f"inspection_id: a newer inspection of this vehicle is already certified ({current.number})",
                field="inspection_id",
                rule="newer_certified",
            )
    _refuse_if_weighed_again(session, inspection, field="inspection_id")
    expires_at = add_months(now, settings.certificate_validity_months)
    certificate = _create(
        session,
        number=str(number),
        inspection=inspection,
        actor=actor,
        settings=settings,
        issued_at=now,
        expires_at=expires_at,
        supersedes=current,
        action="issue",
        reason=None,
        second_language=language,
    )
    return Issued(certificate=certificate, created=True)


def reissue_certificate(
    session: Session,
    *,
    number: str,
    actor: Actor,
    reason: str,
    settings: Settings,
    now: datetime | None = None,
) -> Certificate:
    """A new certificate for the same inspection that supersedes this one, keeping its expiry (admins)."""
    if not actor.admin:
        raise Forbidden("only an administrator may reissue a certificate", field="actor", rule="admin")
    reason = _reason(reason)
    now = now or utcnow()
    old = get_certificate(session, number)
    allocated = allocate_number(session, now.year)
    session.refresh(old)
    status = certificate_status(old, now)
    if status != "issued":
        session.rollback()
        raise Conflict(
            f"number: {document_kind(old.kind)} {old.number} is {status}; only a current one can be reissued",
            field="number",
            rule=status,
        )
    inspection = session.get(Inspection, old.inspection_id)
    assert inspection is not None
    _refuse_if_weighed_again(session, inspection, field="number")
    return _create(
        session,
        number=str(allocated),
        inspection=inspection,
        actor=actor,
        settings=settings,
        issued_at=now,
        expires_at=old.expires_at,
        supersedes=old,
        action="reissue",
        reason=reason,
        second_language=old.second_language,  # the new paper speaks as the one it replaces
    )


def revoke_certificate(
    session: Session, *, number: str, actor: Actor, reason: str, now: datetime | None = None
) -> Certificate:
    """Revoke a certificate for good, with a reason, by an administrator; recorded in the audit log."""
    if not actor.admin:
        raise Forbidden("only an administrator may revoke a certificate", field="actor", rule="admin")
    reason = _reason(reason)
    certificate = get_certificate(session, number)
    if certificate.revocation is not None:
        raise Conflict(
            f"number: {document_kind(certificate.kind)} {certificate.number} is already revoked",
            field="number",
            rule="revoked",
        )
    at = now or utcnow()
    session.add(
        CertificateRevocation(certificate=certificate, revoked_at=at, revoked_by=actor.label, reason=reason)
    )
    session.add(
        CertificateAudit(
            certificate_id=certificate.id, action="revoke", actor=actor.label, at=at, reason=reason
        )
    )
    try:
        session.commit()
    except IntegrityError as error:  # revoked at the same moment by someone else
        session.rollback()
        raise Conflict(
            f"number: {document_kind(certificate.kind)} {certificate.number} is already revoked",
            field="number",
            rule="revoked",
        ) from error
    session.refresh(certificate)
    return certificate


def _refuse_if_weighed_again(session: Session, inspection: Inspection, *, field: str) -> None:
    """409 when the vehicle was weighed after this inspection and found otherwise (another verdict or
    occupancy): a certificate never says more than the newest weighing found (the database refuses
    the row too)."""
    later = session.scalar(
        select(Inspection.id)
        .where(Inspection.vehicle_id == inspection.vehicle_id)
        .where(
            or_(
                Inspection.compliant != inspection.compliant,
                Inspection.max_compliant_occupants != inspection.max_compliant_occupants,
            )
        )
        .where(
            or_(
                Inspection.created_at > inspection.created_at,
                and_(Inspection.created_at == inspection.created_at, Inspection.id > inspection.id),
            )
        )
        .order_by(Inspection.created_at.desc(), Inspection.id.desc())
        .limit(1)
    )
    if later is not None:
        session.rollback()
        raise Conflict(
            f"{field}: {inspection.registration_number} was weighed again after inspection {inspection.id} "
            f"and found otherwise (inspection {later}); certify the newest weighing",
            field=field,
            rule="newer_inspection",
        )


def _reason(reason: str) -> str:
    reason = " ".join(checked("reason", reason, max_length=REASON_LENGTH, required=False).split())
    if not reason:
        raise InvalidInput("reason: say why, in a few words", field="reason", rule="required")
    return reason


def _create(
    session: Session,
    *,
    number: str,
    inspection: Inspection,
    actor: Actor,
    settings: Settings,
    issued_at: datetime,
    expires_at: datetime,
    supersedes: Certificate | None,
    action: Literal["issue", "reissue"],
    reason: str | None,
    second_language: str | None = None,
) -> Certificate:
    """Sign, render and store a certificate with its audit entries, and commit."""
    if settings.require_calibration and inspection.calibration_valid_until is None:
        session.rollback()  # the number allocated is not used
        raise calibration_required(inspection)
    # The facts are frozen in English, whatever language the issuing page is shown in: English is
    # the paper's binding text (the second language is worded from them when the paper is drawn).
    with use_locale(ENGLISH):
        facts = facts_of(
            session,
            inspection,
            authority=settings.issuing_authority,
            issued_by=actor.shown_as,
            ballast_x_m=settings.ballast_x_m,
        )
    kind = "compliant" if facts.compliant else "refusal"
    signer = current_signer(session, settings)
    claims = Claims(
        number=number,
        registration=facts.vehicle.registration_number,
        issued=local_date(issued_at),
        expires=local_date(expires_at),
        verdict=verdict_mark(facts.compliant),
        max_occupants=facts.max_compliant_occupants,
        issued_at=issued_at,
        expires_at=expires_at,
        issuer=issuer_claim(settings.base_url),
    )
    token = sign_payload(claims, kid=signer.kid, key=signer)
    base = verify_base(settings)
    from app.certificates.pdf import CertificateDocument  # beside the PDF library: see render_pdf

    pdf = render_pdf(
        CertificateDocument(
            number=number,
            kind=kind,
            issued_at=issued_at,
            expires_at=expires_at,
            facts=facts,
            verify_url=base,
            qr_url=qr_url_of(settings.base_url, number, token),
            second_language=second_language,
        )
    )
    number_parts = parse_number(number)
    certificate = Certificate(
        number=number,
        year=number_parts.year,
        sequence=number_parts.sequence,
        kind=kind,
        inspection_id=inspection.id,
        vehicle_id=inspection.vehicle_id,
        registration_number=facts.vehicle.registration_number,
        compliant=facts.compliant,
        max_compliant_occupants=facts.max_compliant_occupants,
        issued_at=issued_at,
        expires_at=expires_at,
        issued_by=actor.label,
        issued_by_station_id=actor.station_id,
        issued_by_user_id=actor.user_id,
        supersedes=supersedes,
        facts=facts.to_json(),
        key_id=signer.kid,
        qr_payload=token,
        pdf=pdf,
        pdf_sha256=_sha256(pdf),
        second_language=second_language,
    )
    session.add(certificate)
    session.flush()
    session.add(
        CertificateAudit(
            certificate_id=certificate.id, action=action, actor=actor.label, at=issued_at, reason=reason
        )
    )
    if supersedes is not None:
        session.add(
            CertificateAudit(
                certificate_id=supersedes.id,
                action="supersede",
                actor=actor.label,
                at=issued_at,
                reason=f"superseded by {number}" + (f": {reason}" if reason else ""),
            )
        )
    session.commit()
    return certificate


def calibration_required(inspection: Inspection) -> CalibrationRefused:
    """The refusal to issue for a weighing with no scale calibration on record, when one is required."""
    where = (
        f"the scale of {inspection.station.name} had no calibration on record when it was weighed"
        if inspection.station is not None
        else "it was recorded without a station, so no scale calibration is on record"
    )
    return CalibrationRefused(
        f"inspection_id: no certificate or refusal can be issued for inspection {inspection.id}: {where}, "
        "and this service requires one (TRIKECERT_REQUIRE_CALIBRATION). Weigh the vehicle again on a "
        "station scale whose calibration is recorded.",
        field="inspection_id",
        rule="calibration_missing",
    )


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()
