"""The vehicle's figures for the estimates: a page form that records a new revision (the old ones stay)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from decimal import Decimal

from fastapi import APIRouter
from starlette.datastructures import FormData
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import CurrentLogin, PostLogin
from app.accounts.sessions import set_flash
from app.dynamics.lookups import display_registration, find_vehicle
from app.dynamics.models import DYNAMICS_FIELDS
from app.dynamics.protocols import FiguredVehicle
from app.dynamics.service import DynamicsFigures, record_figures, revision_figures, seat_heights
from app.errors import NotFound, ServiceError
from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.stability.layout import DELTA, Layout, layout_named
from app.web.deps import FormDep, SessionDep
from app.web.formatting import NOT_RECORDED, or_not_recorded
from app.web.forms import FormErrors, parse_decimal, text
from app.web.templating import render

router = APIRouter(prefix="/vehicles", include_in_schema=False)

# Each figure: its label with the unit, its hint, and the example in the message when it is not a number.
# Marked with N_ and translated where shown (labels()), never frozen in one language at import.
LABELS = {
    "track_m": (N_("Rear track (m)"), N_("Between the centres of the two rear tyres, like 1.150")),
    "front_track_m": (N_("Front track (m)"), N_("Between the centres of the two front tyres, like 1.200")),
    "wheel_radius_m": (
        N_("Loaded rear wheel radius (m)"),
        N_("From the rear axle centre to the ground, like 0.190"),
    ),
    "front_cornering_stiffness_n_per_rad": (
        N_("Front tyre cornering stiffness (N/rad)"),
        N_("From the tyre maker or a test, like 8000; an estimate"),
    ),
    "rear_cornering_stiffness_n_per_rad": (
        N_("Each rear tyre's cornering stiffness (N/rad)"),
        N_("From the tyre maker or a test, like 8000; an estimate"),
    ),
    "drag_area_m2": (
        N_("Drag area, Cd × A (m²)"),
        N_("Drag coefficient times frontal area, like 1.6; an estimate"),
    ),
    "centre_of_pressure_height_m": (
        N_("Centre of pressure height (m)"),
        N_("Where the wind's force acts, above the ground, like 0.900; an estimate"),
    ),
}
# A layout whose tyres are not the delta's one front and two rear has these words instead.
TWO_FRONT_LABELS = {
    "front_cornering_stiffness_n_per_rad": (
        N_("Each front tyre's cornering stiffness (N/rad)"),
        N_("From the tyre maker or a test, like 8000; an estimate"),
    ),
}
ONE_REAR_LABELS = {
    "rear_cornering_stiffness_n_per_rad": (
        N_("Rear tyre cornering stiffness (N/rad)"),
        N_("From the tyre maker or a test, like 8000; an estimate"),
    ),
}
SEAT_HINT = N_(
    "The seated person's centre of gravity above the ground, some 0.2 m above the seat top, like 0.75"
)


def _words(layout: Layout) -> dict[str, tuple[str, str]]:
    """Each figure's label and hint as marked, for the layout's tyres."""
    return {
        **LABELS,
        **(TWO_FRONT_LABELS if layout.n_front > 1 else {}),
        **(ONE_REAR_LABELS if layout.n_rear == 1 else {}),
    }


def labels(layout: Layout = DELTA) -> dict[str, tuple[str, str]]:
    """Each figure's label and hint in the active language, for the layout's tyres."""
    return {name: (_(label), _(hint)) for name, (label, hint) in _words(layout).items()}


def page_fields(vehicle: FiguredVehicle) -> list[str]:
    """The figures a vehicle's pages ask for and show, in order: a front track only for two front wheels,
    a rear track only for two rear wheels."""
    layout = layout_named(vehicle.layout)
    tracks = ["track_m"] * (layout.n_rear > 1) + ["front_track_m"] * (layout.n_front > 1)
    return [*tracks, *(name for name in DYNAMICS_FIELDS if not name.endswith("track_m"))]


def seat_input(index: int) -> str:
    """The input of one seat's height."""
    return f"seat_z_m_{index}"


# A figure that is not a number: one sentence per figure, so each language words it whole.
NOT_A_NUMBER = {
    "track_m": N_("Enter the rear track (m) as a number, or leave it blank"),
    "wheel_radius_m": N_("Enter the loaded rear wheel radius (m) as a number, or leave it blank"),
    "front_cornering_stiffness_n_per_rad": N_(
        "Enter the front tyre cornering stiffness (N/rad) as a number, or leave it blank"
    ),
    "rear_cornering_stiffness_n_per_rad": N_(
        "Enter the each rear tyre's cornering stiffness (N/rad) as a number, or leave it blank"
    ),
    "drag_area_m2": N_("Enter the drag area, Cd × A (m²) as a number, or leave it blank"),
    "centre_of_pressure_height_m": N_(
        "Enter the centre of pressure height (m) as a number, or leave it blank"
    ),
}
TWO_FRONT_NOT_A_NUMBER = {
    "front_cornering_stiffness_n_per_rad": N_(
        "Enter each front tyre's cornering stiffness (N/rad) as a number, or leave it blank"
    ),
}
ONE_REAR_NOT_A_NUMBER = {
    "rear_cornering_stiffness_n_per_rad": N_(
        "Enter the rear tyre cornering stiffness (N/rad) as a number, or leave it blank"
    ),
}
NOT_A_SEAT_HEIGHT = N_("Enter the seated height (m) as a number, or leave it blank")


@dataclass
class FiguresForm:
    """The parsed form, its raw values and its errors."""

    values: dict[str, str]
    errors: FormErrors = field(default_factory=FormErrors)
    figures: DynamicsFigures | None = None


def read_figures_form(form: FormData, seat_count: int, layout: Layout = DELTA) -> FiguresForm:
    """Parse the form; a blank field is a figure not known."""
    messages = {
        **NOT_A_NUMBER,
        **(TWO_FRONT_NOT_A_NUMBER if layout.n_front > 1 else {}),
        **(ONE_REAR_NOT_A_NUMBER if layout.n_rear == 1 else {}),
    }
    errors = FormErrors()
    names = [*DYNAMICS_FIELDS, *(seat_input(i) for i in range(seat_count))]
    values = {name: text(form, name, errors, limit=20) for name in names}
    parsed: dict[str, Decimal | None] = {}
    for name in names:
        parsed[name] = parse_decimal(values[name]) if values[name] else None
        if values[name] and parsed[name] is None and name not in errors.messages:
            errors.add(name, _(messages.get(name, NOT_A_SEAT_HEIGHT)))
    result = FiguresForm(values=values, errors=errors)
    if not errors:
        result.figures = DynamicsFigures(
            seat_heights_m=seat_heights([parsed[seat_input(i)] for i in range(seat_count)]),
            **{name: parsed[name] for name in DYNAMICS_FIELDS},
        )
    return result


def _vehicle(session: SessionDep, registration_key: str) -> FiguredVehicle:
    vehicle = find_vehicle(session, registration_key)
    if vehicle is None:
        raise NotFound(
            _("No vehicle %(plate)s is registered") % {"plate": display_registration(registration_key)}
        )
    return vehicle


def current_values(vehicle: FiguredVehicle) -> dict[str, str]:
    """The form pre-filled with the figures in force."""
    revisions = vehicle.dynamics_revisions
    figures = revision_figures(revisions[-1] if revisions else None)
    values = {name: _shown(getattr(figures, name)) for name in DYNAMICS_FIELDS}
    for index in range(len(vehicle.seats)):
        heights = figures.seat_heights_m
        values[seat_input(index)] = _shown(heights[index] if index < len(heights) else None)
    return values


def _shown(value: Decimal | None) -> str:
    return "" if value is None else f"{value.normalize():f}"


def _page(
    request: Request, vehicle: FiguredVehicle, values: dict[str, str], errors: FormErrors, status: int
) -> Response:
    return render(
        request,
        "vehicles/dynamics.html",
        {
            "vehicle": vehicle,
            "values": values,
            "errors": errors.messages,
            "labels": labels(layout_named(vehicle.layout)),
            "track_fields": [name for name in page_fields(vehicle) if name.endswith("track_m")],
            "seat_hint": _(SEAT_HINT),
        },
        status_code=status,
    )


@router.get("/{registration_key}/dynamics")
def figures_form(
    request: Request, session: SessionDep, login: CurrentLogin, registration_key: str
) -> Response:
    """The form with the vehicle's figures for the estimates, as in force."""
    vehicle = _vehicle(session, registration_key)
    return _page(request, vehicle, current_values(vehicle), FormErrors(), 200)


@router.post("/{registration_key}/dynamics")
def change_figures(
    request: Request, session: SessionDep, login: PostLogin, form: FormDep, registration_key: str
) -> Response:
    """Record the figures as a new revision (unchanged figures record nothing), or show the problems."""
    vehicle = _vehicle(session, registration_key)
    parsed = read_figures_form(form, len(vehicle.seats), layout_named(vehicle.layout))
    if parsed.figures is not None:
        revisions = vehicle.dynamics_revisions
        current = revision_figures(revisions[-1] if revisions else None)
        # A figure the page does not ask for (a tadpole's rear track, sent by the API) stays as recorded.
        shown = page_fields(vehicle)
        unasked = {name: getattr(current, name) for name in DYNAMICS_FIELDS if name not in shown}
        parsed.figures = replace(parsed.figures, **unasked)
        if parsed.figures == current:
            set_flash(session, login, _("The figures for the estimates are unchanged."))
            return RedirectResponse(f"/vehicles/{vehicle.registration_key}", status_code=303)
        try:
            revision = record_figures(session, vehicle, parsed.figures)
        except ServiceError as error:
            input_for = {name: name for name in DYNAMICS_FIELDS}
            input_for.update({f"seats[{i}].z_m": seat_input(i) for i in range(len(vehicle.seats))})
            parsed.errors.add_problems(error.problems, input_for, DYNAMICS_FIELDS[0])
        else:
            set_flash(
                session,
                login,
                _("Figures for the estimates recorded (revision %(n)s).") % {"n": revision.revision},
            )
            return RedirectResponse(f"/vehicles/{vehicle.registration_key}", status_code=303)
    return _page(request, vehicle, parsed.values, parsed.errors, 422)


def figures_rows(vehicle: FiguredVehicle) -> dict[str, object]:
    """The vehicle page's summary of the figures in force: (label, value) rows and the revision."""
    revisions = vehicle.dynamics_revisions
    values = current_values(vehicle)
    fields = page_fields(vehicle)
    words = labels(layout_named(vehicle.layout))
    rows = [(words[name][0], or_not_recorded(values[name])) for name in fields]
    heights = [str(or_not_recorded(values[seat_input(i)])) for i in range(len(vehicle.seats))]
    shown = NOT_RECORDED if all(h == NOT_RECORDED for h in heights) else ", ".join(heights)
    rows.insert(fields.index("wheel_radius_m") + 1, (_("Seated heights, driver first (m)"), shown))
    return {"rows": rows, "revision": revisions[-1].revision if revisions else None}
