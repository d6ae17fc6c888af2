"""The officers' "Assess a model" pages: pick make, model and year, see the vehicles, confirm, read it."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import CurrentLogin, PostLogin
from app.accounts.sessions import set_flash
from app.api.ids import TypeAssessmentId
from app.config import get_settings
from app.errors import ServiceError
from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.inspections.models import Inspection
from app.stability.model import layout_of_rules
from app.type_assessments.chart import SpreadPoint, spread_chart
from app.type_assessments.models import TypeAssessmentRecord
from app.type_assessments.service import (
    TypeRequest,
    create_type_assessment,
    get_type_assessment,
    inspections_for,
    known_models,
)
from app.web import submissions
from app.web.deps import FormDep, SessionDep
from app.web.forms import FormErrors, query_text, readable
from app.web.refusals import translated_refusal
from app.web.templating import render
from app.wording import case_name, type_occupancy_sentence, verdict_sentence

router = APIRouter(include_in_schema=False)
FIELDS = ("make", "model", "model_year")
TEXT_LIMITS = {"make": 80, "model": 80, "model_year": 4}


def read_model(raw: dict[str, str], errors: FormErrors) -> tuple[dict[str, str], TypeRequest | None]:
    """The make, model and year typed, and the request they make (None while incomplete or refused)."""
    values = {name: query_text(raw.get(name, ""), name, errors, limit=TEXT_LIMITS[name]) for name in FIELDS}
    values = {name: value.strip() for name, value in values.items()}
    year: int | None = None
    if values["model_year"]:
        text = values["model_year"]
        if not (text.isascii() and text.isdigit() and 1950 <= int(text) <= 2100):
            errors.add("model_year", _("Enter the model year as a year from 1950 to 2100, or leave it blank"))
        else:
            year = int(text)
    missing = {
        "make": N_("Enter the make, as on the vehicles' registration"),
        "model": N_("Enter the model, as on the vehicles' registration"),
    }
    for name, message in missing.items():
        if not values[name] and name not in errors.messages:
            errors.add(name, _(message))
    if errors:
        return values, None
    return values, TypeRequest(values["make"], values["model"], year)


def _new_page(
    request: Request,
    session: Session,
    values: dict[str, str],
    errors: FormErrors,
    *,
    inspections: list[Inspection] | None = None,
    shortage: str = "",
    token: str = "",
    status_code: int = 200,
) -> Response:
    return render(
        request,
        "type_assessments/new.html",
        {
            "values": values,
            "errors": errors.messages,
            "models": known_models(session),
            "inspections": inspections,
            "shortage": shortage,
            "form_token": token or submissions.new_form_token(),
            "active_page": "types",
        },
        status_code=status_code,
    )


@router.get("/type-assessments/new")
def new_type_assessment(request: Request, session: SessionDep, login: CurrentLogin) -> Response:
    """Pick a make, model and year; with them, the vehicles' latest inspections it would use."""
    query = request.query_params
    if not any(query.get(name) for name in FIELDS):
        return _new_page(request, session, dict.fromkeys(FIELDS, ""), FormErrors())
    errors = FormErrors()
    values, wanted = read_model({name: query.get(name, "") for name in FIELDS}, errors)
    if wanted is None:
        return _new_page(request, session, values, errors, status_code=422)
    try:
        found = inspections_for(session, wanted)
    except ServiceError as error:  # fewer than two vehicles: say so beside the list, not as an error
        return _new_page(
            request,
            session,
            values,
            errors,
            inspections=[],
            shortage=translated_refusal(readable(error.message)),
        )
    return _new_page(request, session, values, errors, inspections=found)


@router.post("/type-assessments")
def create(request: Request, session: SessionDep, login: PostLogin, form: FormDep) -> Response:
    """Assess the model and store it once; a repeated submission of the same form goes to the first."""
    token = str(form.get("form_token") or "")
    if not submissions.valid_token(token):
        token = submissions.new_form_token()
    elif (done := submissions.previous_result(session, token)) is not None:
        return RedirectResponse(done, status_code=303)
    errors = FormErrors()
    values, wanted = read_model({name: str(form.get(name) or "") for name in FIELDS}, errors)
    if wanted is None:
        return _new_page(request, session, values, errors, token=token, status_code=422)

    def store_token(db: Session, record: TypeAssessmentRecord) -> None:
        submissions.remember(
            db, token=token, user_id=login.user_id, redirect_path=f"/type-assessments/{record.id}"
        )

    try:
        record = create_type_assessment(
            session,
            request=wanted,
            rules=get_settings().rules(),
            user_id=login.user_id,
            on_stored=store_token,
        )
    except ServiceError as error:
        session.rollback()
        errors.add("model", translated_refusal(readable(error.message)))
        return _new_page(request, session, values, errors, token=token, status_code=422)
    except IntegrityError:
        session.rollback()  # the same form was stored by a simultaneous submission
        done = submissions.previous_result(session, token)
        if done is None:
            raise
        return RedirectResponse(done, status_code=303)
    set_flash(session, login, _("Type assessment recorded."))
    return RedirectResponse(f"/type-assessments/{record.id}", status_code=303)


def page_context(record: TypeAssessmentRecord) -> dict[str, Any]:
    """The type's Table 4 rows, its spread, the verdict in words and the chart."""
    cases = record.cases
    members = [m.inspection for m in record.members]
    vehicle_cases = [{c.occupants: c for c in inspection.loading_cases} for inspection in members]
    points = [
        SpreadPoint(
            occupants=case.occupants,
            vehicles=tuple(
                (float(v[case.occupants].lsf), v[case.occupants].compliant) for v in vehicle_cases
            ),
            mean=float(case.mean_lsf),
            upper=float(case.upper_95_lsf),
            confident=case.confident_compliant,
        )
        for case in cases
    ]
    return {
        "record": record,
        "members": members,
        "rows": [
            {
                "occupants": c.occupants,
                "label": case_name(c.occupants),
                "total_kg": c.total_kg,
                "rear_kg": c.rear_kg,
                "lsf": c.lsf,
                "variance": c.variance,
                "compliant": c.compliant,
                "measured": False,
            }
            for c in cases
        ],
        "verdict": verdict_sentence(
            [(c.occupants, c.confident_compliant) for c in cases], record.max_compliant_occupants
        ),
        "occupancy": type_occupancy_sentence(record.compliant, record.max_compliant_occupants),
        "chart": spread_chart(points, limit=layout_of_rules(record.rules_version).limit),
        "active_page": "types",
    }


@router.get("/type-assessments/{type_assessment_id}")
def type_assessment_page(
    request: Request, session: SessionDep, login: CurrentLogin, type_assessment_id: TypeAssessmentId
) -> Response:
    """The stored type assessment: verdict, the type's Table 4, the spread, the chart, the vehicles."""
    record = get_type_assessment(session, type_assessment_id)
    return render(request, "type_assessments/show.html", page_context(record))
