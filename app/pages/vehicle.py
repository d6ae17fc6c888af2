"""A vehicle's page: its document in force and latest verdict, its particulars and figures, its
inspection history."""

from __future__ import annotations

from fastapi import APIRouter
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import CurrentLogin
from app.certificates.in_force import current_document
from app.dynamics.views import figures_rows
from app.errors import NotFound
from app.i18n.active import gettext as _
from app.inspections.service import InspectionFilter, get_inspection, list_inspections
from app.inspections.views import result_context
from app.vehicles.service import display_registration, find_vehicle
from app.web.deps import SessionDep
from app.web.templating import render

router = APIRouter(prefix="/vehicles", include_in_schema=False)
HISTORY_LENGTH = 20


@router.get("/{registration_key}")
def vehicle_page(
    request: Request, session: SessionDep, login: CurrentLogin, registration_key: str
) -> Response:
    """The vehicle: its document in force and latest verdict first, then its particulars, seats and
    figures, then its inspection history."""
    vehicle = find_vehicle(session, registration_key)
    if vehicle is None:
        raise NotFound(
            _("No vehicle %(plate)s is registered") % {"plate": display_registration(registration_key)}
        )
    if registration_key != vehicle.registration_key:
        return RedirectResponse(f"/vehicles/{vehicle.registration_key}", status_code=303)
    inspections, total = list_inspections(
        session,
        where=InspectionFilter(registration_number=vehicle.registration_key),
        limit=HISTORY_LENGTH,
        offset=0,
    )
    return render(
        request,
        "vehicles/show.html",
        {
            "vehicle": vehicle,
            "inspections": inspections,
            "total": total,
            "figures": figures_rows(vehicle),
            "current": current_document(session, vehicle.id),
            "latest": result_context(session, get_inspection(session, inspections[0].id))
            if inspections
            else None,
        },
    )
