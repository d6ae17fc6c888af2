"""An inspection's page: its result, the estimates, what would make it comply, and its documents."""

from __future__ import annotations

from fastapi import APIRouter
from starlette.requests import Request
from starlette.responses import Response

from app.accounts.deps import CurrentLogin
from app.api.ids import InspectionId
from app.certificates.actors import issued_by, recorded_by
from app.certificates.facts import calibration_words
from app.certificates.in_force import why_not_issuable
from app.certificates.languages import paper_language_choices
from app.certificates.records import certificates_of_inspection
from app.config import get_settings
from app.dynamics.presentation import dynamics_context
from app.inspections.models import Inspection
from app.inspections.service import get_inspection
from app.inspections.views import result_context
from app.remedies.views import remedies_context
from app.web.deps import SessionDep
from app.web.templating import render

router = APIRouter(include_in_schema=False)


def raw_readings(inspection: Inspection) -> dict[str, list[str]]:
    """The base weighing's readings per wheel, as typed."""
    found: dict[str, list[str]] = {}
    for reading in inspection.readings:
        if reading.case_occupants == 0:
            found.setdefault(reading.wheel, []).append(f"{reading.value_kg.normalize():f}")
    return found


@router.get("/inspections/{inspection_id}")
def inspection_page(
    request: Request, session: SessionDep, login: CurrentLogin, inspection_id: InspectionId
) -> Response:
    """Table 4, the verdict in words, the certified occupancy, the chart and what would make it comply."""
    inspection = get_inspection(session, inspection_id)
    context = result_context(session, inspection)
    remedies, remedy_errors = (
        (None, None) if inspection.compliant else remedies_context(inspection, request.query_params)
    )
    certificates = certificates_of_inspection(session, inspection.id)
    context.update(dynamics_context(inspection))
    context.update(
        recorded_by=recorded_by(session, inspection),
        calibration=calibration_words(inspection.calibration_certificate, inspection.calibration_valid_until),
        raw=raw_readings(inspection),
        certificates=certificates,
        not_issuable=why_not_issuable(session, inspection),
        paper_languages=paper_language_choices(get_settings()),
        issuers={
            certificate.id: issued_by(
                session,
                user_id=certificate.issued_by_user_id,
                station_id=certificate.issued_by_station_id,
                label=certificate.issued_by,
            )
            for certificate, _status in certificates
        },
        remedies=remedies,
        errors=remedy_errors.messages if remedy_errors else {},
    )
    return render(request, "inspections/show.html", context, status_code=422 if remedy_errors else 200)
