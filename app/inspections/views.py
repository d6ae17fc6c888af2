"""Inspection pages: the new-inspection form, the result (Table 4, verdict, chart) and the lists."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter
from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import CurrentLogin, PostLogin
from app.accounts.sessions import set_flash
from app.api.ids import IdChoice, PageNumber
from app.config import get_settings
from app.errors import NotFound, ServiceError
from app.i18n.active import gettext as _
from app.ids import parse_id
from app.inspections.forms import (
    READINGS_PER_WHEEL,
    initial_values,
    read_inspection_form,
    wheel_labels,
    wheels_of,
)
from app.inspections.models import Inspection
from app.inspections.service import InspectionFilter, list_inspections, record_inspection
from app.stability import layout_named
from app.stations.models import Station
from app.vehicles.models import Vehicle
from app.vehicles.service import display_registration, find_vehicle
from app.web import submissions
from app.web.chart import ChartPoint, lsf_chart, short_label
from app.web.deps import FormDep, SessionDep
from app.web.formatting import day_bounds, local_today, long_date
from app.web.forms import FormErrors, query_text, read_date
from app.web.templating import render
from app.wording import case_name, occupancy_sentence, verdict_sentence

router = APIRouter(include_in_schema=False)


def _vehicle(session: Session, registration_key: str) -> Vehicle:
    vehicle = find_vehicle(session, registration_key)
    if vehicle is None:
        raise NotFound(
            _("No vehicle %(plate)s is registered") % {"plate": display_registration(registration_key)}
        )
    return vehicle


def _form_page(
    request: Request,
    vehicle: Vehicle,
    values: dict[str, str],
    token: str,
    errors: FormErrors,
    status_code: int,
) -> Response:
    return render(
        request,
        "inspections/new.html",
        {
            "vehicle": vehicle,
            "values": values,
            "errors": errors.messages,
            "form_token": token,
            "readings_per_wheel": READINGS_PER_WHEEL,
            "wheels": [(w, *wheel_labels(w)) for w in wheels_of(vehicle)],
            "measured_open": any(
                k.startswith("measured_") and (v or k in errors.messages) for k, v in values.items()
            ),
        },
        status_code=status_code,
    )


@router.get("/vehicles/{registration_key}/inspections/new")
def new_inspection_form(
    request: Request, session: SessionDep, login: CurrentLogin, registration_key: str
) -> Response:
    """The form, pre-filled with the vehicle's wheelbase and seats and the standard occupant mass."""
    vehicle = _vehicle(session, registration_key)
    values = initial_values(vehicle, get_settings().occupant_mass_kg)
    return _form_page(request, vehicle, values, submissions.new_form_token(), FormErrors(), 200)


@router.post("/vehicles/{registration_key}/inspections/new")
def create_inspection(
    request: Request, session: SessionDep, login: PostLogin, form: FormDep, registration_key: str
) -> Response:
    """Assess and store once; a repeated submission of the same form goes to the first result."""
    vehicle = _vehicle(session, registration_key)
    token = str(form.get("form_token") or "")
    if not submissions.valid_token(token):
        token = submissions.new_form_token()
    elif (done := submissions.previous_result(session, token)) is not None:
        return RedirectResponse(done, status_code=303)
    parsed = read_inspection_form(form, vehicle)
    if parsed.request is not None:

        def store_token(db: Session, inspection_id: int) -> None:
            submissions.remember(
                db, token=token, user_id=login.user_id, redirect_path=f"/inspections/{inspection_id}"
            )

        try:
            inspection = record_inspection(
                session,
                request=parsed.request,
                rules=get_settings().rules(),
                user_id=login.user_id,
                on_stored=store_token,
            )
        except ServiceError as error:
            parsed.errors.add_problems(error.problems, parsed.input_for, "front_kg_1")
            if not error.problems:
                parsed.errors.add("front_kg_1", error.message)
        except IntegrityError:
            session.rollback()  # the same form was stored by a simultaneous submission
            done = submissions.previous_result(session, token)
            if done is None:
                raise
            return RedirectResponse(done, status_code=303)
        else:
            set_flash(session, login, _("Inspection recorded."))
            return RedirectResponse(f"/inspections/{inspection.id}", status_code=303)
    return _form_page(request, vehicle, parsed.values, token, parsed.errors, 422)


def table_rows(inspection: Inspection) -> list[dict[str, Any]]:
    """Table 4 of the study for this inspection, one row per loading case."""
    return [
        {
            "occupants": case.occupants,
            "label": case_name(case.occupants),
            "total_kg": case.total_kg,
            "rear_kg": case.rear_kg,
            "lsf": case.lsf,
            "variance": case.variance,
            "compliant": case.compliant,
            "measured": case.measured,
        }
        for case in inspection.loading_cases
    ]


def result_context(session: Session, inspection: Inspection) -> dict[str, Any]:
    """What the result partial shows: Table 4, the verdict in words, the occupancy and the chart."""
    cases = inspection.loading_cases
    points = [
        ChartPoint(short_label(c.occupants), case_name(c.occupants), float(c.lsf), c.compliant) for c in cases
    ]
    return {
        "inspection": inspection,
        "rows": table_rows(inspection),
        "verdict": verdict_sentence(
            [(c.occupants, c.compliant) for c in cases], inspection.max_compliant_occupants
        ),
        "occupancy": occupancy_sentence(inspection.compliant, inspection.max_compliant_occupants),
        "chart": lsf_chart(points, limit=layout_named(inspection.layout).limit),
    }


VERDICTS = {"": None, "compliant": True, "not-compliant": False}


@router.get("/inspections")
def inspections_page(
    request: Request, session: SessionDep, login: CurrentLogin, station: IdChoice = "", page: PageNumber = 1
) -> Response:
    """Inspections, newest first, filtered by verdict, station, dates and registration, a page at a time."""
    query = request.query_params
    errors = FormErrors()
    values = {
        name: query_text(query.get(name, ""), name, errors, limit=40)
        for name in ("verdict", "from", "to", "registration")
    }
    values["station"] = query_text(station, "station", errors, limit=40)
    if values["verdict"] not in VERDICTS:
        errors.add("verdict", _("Choose compliant, not compliant or all"))
        values["verdict"] = ""
    station_id = parse_id(station)
    if station.strip() and station_id is None:
        errors.add("station", _("Choose a station from the list"))
    since_day, until_day = read_date(values["from"], "from", errors), read_date(values["to"], "to", errors)
    if since_day and until_day and until_day < since_day:
        errors.add("to", _("The 'to' date must be the same as or after the 'from' date"))
        until_day = None
    size = get_settings().page_size
    where = InspectionFilter(
        registration_number=values["registration"] or None,
        compliant=VERDICTS[values["verdict"]],
        station_id=station_id,
        since=day_bounds(since_day)[0] if since_day else None,
        until=day_bounds(until_day)[1] if until_day else None,
    )
    items, total = list_inspections(session, where=where, limit=size, offset=(page - 1) * size)
    kept = {k: v for k, v in values.items() if v}
    return render(
        request,
        "inspections/list.html",
        {
            "items": items,
            "total": total,
            "page": page,
            "pages": max(1, -(-total // size)),
            "first": (page - 1) * size + 1 if items else 0,
            "last": (page - 1) * size + len(items),
            "values": values,
            "errors": errors.messages,
            "kept": kept,
            "stations": session.scalars(select(Station).order_by(Station.name)).all(),
            "today": long_date(local_today()),
        },
        status_code=422 if errors else 200,
    )
