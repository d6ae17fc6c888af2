"""For the officers' pages: a vehicle's document in force, and why an inspection cannot be certified
now (so a page offers no button that could only be refused)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from sqlalchemy import Select, func, select
from sqlalchemy.orm import Session, aliased

from app.certificates.models import Certificate
from app.certificates.records import Status, certificate_status
from app.certificates.service import _current_of_vehicle
from app.inspections.models import Inspection
from app.wording import document_kind


@dataclass(frozen=True)
class Current:
    """A vehicle's newest document that is neither revoked nor superseded, and its status now."""

    certificate: Certificate
    status: Status
    kind: str  # "certificate" or "refusal", as every message words it


def current_document(session: Session, vehicle_id: int, now: datetime | None = None) -> Current | None:
    """The vehicle's document in force (or lapsed: `status` says "expired"), or None when it has none."""
    found = _current_of_vehicle(session, vehicle_id)
    if found is None:
        return None
    return Current(found, certificate_status(found, now), document_kind(found.kind))


def in_force_of(vehicle_ids: Select[int]) -> Select[int, int]:
    """For many vehicles at once (`vehicle_ids`, a query of ids): each one's document in force, or
    lapsed, as `current_document` finds it, as rows of (vehicle_id, certificate_id)."""
    newer = aliased(Certificate)
    superseded = select(newer.supersedes_id).where(newer.supersedes_id.is_not(None))
    return (
        select(Certificate.vehicle_id, func.max(Certificate.id).label("certificate_id"))
        .where(Certificate.vehicle_id.in_(vehicle_ids), Certificate.revocation == None)  # noqa: E711
        .where(Certificate.id.not_in(superseded))
        .group_by(Certificate.vehicle_id)
    )


def why_not_issuable(session: Session, inspection: Inspection, now: datetime | None = None) -> str | None:
    """Why issuing from this inspection would be refused (the rules of `issue_certificate`), in words;
    None when the button may be offered."""
    current = current_document(session, inspection.vehicle_id, now)
    if current is not None and current.certificate.inspection_id == inspection.id:
        if current.status == "expired":
            return f"Its {current.kind} {current.certificate.number} has expired: weigh the vehicle again."
        return None
    revoked = session.scalars(
        select(Certificate)
        .where(Certificate.inspection_id == inspection.id, Certificate.revocation != None)  # noqa: E711
        .limit(1)
    ).first()
    if revoked is not None:
        return f"Its {document_kind(revoked.kind)} {revoked.number} was revoked: weigh the vehicle again."
    if current is not None:
        shown = session.get(Inspection, current.certificate.inspection_id)
        assert shown is not None
        if (shown.created_at, shown.id) > (inspection.created_at, inspection.id):
            return (
                f"A newer inspection of this vehicle, No. {shown.id}, is already certified "
                f"({current.kind} {current.certificate.number}): nothing is issued from this older one."
            )
    return None
