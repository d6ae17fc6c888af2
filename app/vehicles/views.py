"""Vehicle pages: register one with its seat layout, find one by registration (its page: app/pages)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import CurrentLogin, PostLogin
from app.accounts.sessions import set_flash
from app.config import get_settings
from app.errors import Conflict, ServiceError
from app.i18n.active import gettext as _
from app.stability import LAYOUTS
from app.text import without_refused
from app.vehicles.forms import PASSENGER_ROWS, read_vehicle_form
from app.vehicles.service import display_registration, find_vehicle, normalise_registration, register_vehicle
from app.web.deps import FormDep, SessionDep
from app.web.forms import FormErrors, query_text
from app.web.templating import render

router = APIRouter(prefix="/vehicles", include_in_schema=False)


@router.get("/find")
def find_page(
    request: Request,
    session: SessionDep,
    login: CurrentLogin,
    registration_number: Annotated[str | None, Query()] = None,
) -> Response:
    """Find a vehicle by registration (case, spaces and hyphens ignored)."""
    errors = FormErrors()
    shown, status = "", 200
    if registration_number is not None:
        wanted = query_text(registration_number, "registration_number", errors, limit=64)
        shown = wanted or without_refused(registration_number)
        status = 422 if errors else 404
        if errors:
            pass
        elif not wanted:
            errors.add(
                "registration_number",
                _("Enter a registration number, like %(plate)s") % {"plate": "BDG 252 QH"},
            )
        elif (vehicle := find_vehicle(session, wanted)) is not None:
            return RedirectResponse(f"/vehicles/{vehicle.registration_key}", status_code=303)
        else:
            errors.add(
                "registration_number",
                _("No vehicle %(plate)s is registered. Check the number, or register the vehicle")
                % {"plate": display_registration(wanted)},
            )
    return render(
        request,
        "vehicles/find.html",
        {"values": {"registration_number": shown}, "errors": errors.messages},
        status_code=status if errors and registration_number else 200,
    )


@router.get("/new")
def new_vehicle_form(request: Request, login: CurrentLogin) -> Response:
    """The form to register a vehicle and its seat layout."""
    return render(
        request,
        "vehicles/new.html",
        {"passenger_rows": PASSENGER_ROWS, "layouts": LAYOUTS, "values": {"layout": "delta"}},
    )


@router.post("/new")
def register(request: Request, session: SessionDep, login: PostLogin, form: FormDep) -> Response:
    """Register the vehicle, or show the form again with the problems and the values kept."""
    parsed = read_vehicle_form(form)
    conflict_key = ""
    if not parsed.errors and parsed.wheelbase_m is not None:
        values = parsed.values
        try:
            vehicle = register_vehicle(
                session,
                registration_number=values["registration_number"],
                make=values["make"],
                model=values["model"],
                model_year=parsed.model_year,
                chassis_number=values["chassis_number"] or None,
                wheelbase_m=parsed.wheelbase_m,
                seats=parsed.seats,
                rules=get_settings().rules(),
                layout=values["layout"],
            )
        except ServiceError as error:
            if isinstance(error, Conflict):
                conflict_key = normalise_registration(values["registration_number"])
            parsed.errors.add_problems(error.problems, parsed.input_for, "registration_number")
        else:
            set_flash(
                session, login, _("Vehicle %(plate)s registered.") % {"plate": vehicle.registration_number}
            )
            return RedirectResponse(f"/vehicles/{vehicle.registration_key}", status_code=303)
    return render(
        request,
        "vehicles/new.html",
        {
            "passenger_rows": PASSENGER_ROWS,
            "layouts": LAYOUTS,
            "values": parsed.values,
            "errors": parsed.errors.messages,
            "conflict_key": conflict_key,
        },
        status_code=422,
    )
