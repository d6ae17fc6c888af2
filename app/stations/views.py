"""Administrator pages for weighbridge stations (list, add, edit, rotate the key, disable, enable) and
a read-only page of the settings in force.

A station key is shown once, on the answer to the POST that made it: it is never stored in clear, so
it cannot travel through a redirect. That answer is never cached (`Cache-Control: no-store`), and its
form carries a one-time token stored in the same transaction as the change, so a double click or a
reload does not add a second station or rotate the key again; it is sent to the station's page instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import UTC, date, datetime
from decimal import Decimal
from typing import Any

from fastapi import APIRouter
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session
from starlette.datastructures import FormData
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import AdminLogin, AdminPost, ConfirmedAdminPost
from app.accounts.models import UserSession
from app.accounts.sessions import set_flash
from app.api.ids import StationId
from app.config import Settings, get_settings
from app.errors import ServiceError
from app.i18n.active import N_, ngettext
from app.i18n.active import gettext as _
from app.stations.details import MAX_CAPACITY_KG, StationDetails
from app.stations.models import Station
from app.stations.service import (
    create_station,
    get_station,
    list_stations,
    rotate_key,
    set_station_active,
    update_station,
)
from app.web import submissions
from app.web.deps import FormDep, SessionDep
from app.web.forms import FormErrors, ascii_digits, parse_decimal, text
from app.web.templating import render

router = APIRouter(include_in_schema=False)

TEXT_LIMITS = {"name": 120, "location": 200, "operator_contact": 200, "calibration_certificate": 64}
DATE_PARTS = ("valid_until_day", "valid_until_month", "valid_until_year")
FIELDS = (*TEXT_LIMITS, *DATE_PARTS, "capacity_kg", "division_kg")
# The service's field names -> the input that shows their message.
INPUT_FOR = {
    "name": "name",
    "location": "location",
    "operator_contact": "operator_contact",
    "calibration_certificate": "calibration_certificate",
    "calibration_valid_until": "valid_until_day",
    "capacity_kg": "capacity_kg",
    "division_kg": "division_kg",
}
REPEATED_FORM = N_(
    "That form had already been sent, so nothing more was done. A station key is shown only once; "
    "if it was not copied, rotate the key."
)
# The missing parts of the calibration date, in the order of the inputs, as one sentence each.
MISSING_DATE_PARTS = {
    (True, False, False): N_("The date the calibration is valid until must include a day"),
    (False, True, False): N_("The date the calibration is valid until must include a month"),
    (False, False, True): N_("The date the calibration is valid until must include a year"),
    (True, True, False): N_("The date the calibration is valid until must include a day and month"),
    (True, False, True): N_("The date the calibration is valid until must include a day and year"),
    (False, True, True): N_("The date the calibration is valid until must include a month and year"),
}


def utc_today() -> date:
    """Today in UTC: the day on which a calibration's last valid day is judged, as the API does."""
    return datetime.now(UTC).date()


def calibration_lapsed(station: Station, today: date) -> bool:
    """True when the station's calibration ended before today (its submissions are refused)."""
    return station.calibration_valid_until is not None and station.calibration_valid_until < today


# ---- the station form: parsing only; the rules stay in app.stations.details and service ------------


@dataclass
class StationForm:
    """The typed form, its raw values (to show again) and its errors."""

    values: dict[str, str]
    errors: FormErrors = field(default_factory=FormErrors)
    name: str = ""
    details: StationDetails = field(default_factory=StationDetails)


def form_values_of(station: Station) -> dict[str, str]:
    """The edit form's values for a station as stored."""
    valid_until = station.calibration_valid_until

    def kg(value: Decimal | None) -> str:
        return "" if value is None else f"{value.normalize():f}"

    return {
        "name": station.name,
        "location": station.location or "",
        "operator_contact": station.operator_contact or "",
        "calibration_certificate": station.calibration_certificate or "",
        "valid_until_day": str(valid_until.day) if valid_until else "",
        "valid_until_month": str(valid_until.month) if valid_until else "",
        "valid_until_year": str(valid_until.year) if valid_until else "",
        "capacity_kg": kg(station.capacity_kg),
        "division_kg": kg(station.division_kg),
    }


def _valid_until(values: dict[str, str], errors: FormErrors) -> date | None:
    parts = [values[name] for name in DATE_PARTS]
    if not any(parts):
        return None
    example = {"example": "31 3 2027"}
    if not all(parts):
        day, month, year = parts
        missing = (not day, not month, not year)
        first = DATE_PARTS[missing.index(True)]
        errors.add(first, _(MISSING_DATE_PARTS[missing]))
        return None
    if not all(ascii_digits(p) for p in parts) or len(parts[2]) != 4:
        errors.add(
            "valid_until_day",
            _("Enter the date the calibration is valid until as numbers, like %(example)s") % example,
        )
        return None
    try:
        return date(int(parts[2]), int(parts[1]), int(parts[0]))
    except ValueError:
        errors.add(
            "valid_until_day",
            _("The calibration's valid-until date must be a real date, like %(example)s") % example,
        )
        return None


def _weight(values: dict[str, str], name: str, errors: FormErrors) -> Decimal | None:
    if not values[name]:
        return None
    value = parse_decimal(values[name])
    capacity = name == "capacity_kg"
    if value is None or not value.is_finite():
        if capacity:
            errors.add(name, _("Enter the capacity as a number of kilograms, like 3000, or leave it blank"))
        else:
            errors.add(
                name, _("Enter the division (e) as a number of kilograms, like 3000, or leave it blank")
            )
        return None
    if value <= 0:
        errors.add(
            name,
            _("The capacity must be more than 0 kg")
            if capacity
            else _("The division (e) must be more than 0 kg"),
        )
        return None
    return value


def read_station_form(form: FormData) -> StationForm:
    """Parse the posted form; blank optional fields mean "not on record"."""
    errors = FormErrors()
    values = {name: text(form, name, errors, limit=TEXT_LIMITS.get(name, 40)) for name in FIELDS}
    result = StationForm(values=values, errors=errors)
    result.name = " ".join(values["name"].split())
    if not result.name:
        errors.add(
            "name", _("Enter the station's name, like %(example)s") % {"example": "Agbara weighbridge"}
        )
    valid_until = _valid_until(values, errors)
    capacity = _weight(values, "capacity_kg", errors)
    division = _weight(values, "division_kg", errors)
    if capacity is not None and capacity > MAX_CAPACITY_KG:
        errors.add(
            "capacity_kg", _("The capacity must be at most %(maximum)s kg") % {"maximum": MAX_CAPACITY_KG}
        )
    if capacity is not None and division is not None and division > capacity:
        errors.add("division_kg", _("The division (e) must not be larger than the capacity"))
    result.details = StationDetails(
        location=values["location"] or None,
        operator_contact=values["operator_contact"] or None,
        calibration_certificate=values["calibration_certificate"] or None,
        calibration_valid_until=valid_until,
        capacity_kg=capacity,
        division_kg=division,
    )
    return result


def _add_service_error(errors: FormErrors, error: ServiceError) -> None:
    errors.add_problems(error.problems, INPUT_FOR, "name")
    if not error.problems:
        errors.add("name", error.message)


def _token(form: FormData) -> str | None:
    """The form's one-time token, or None when it is missing or not one of ours."""
    token = str(form.get("form_token") or "")
    return token if submissions.valid_token(token) else None


def _repeated(session: Session, login: UserSession, token: str) -> Response | None:
    """A redirect to where the first submission of this form led, or None for a fresh form."""
    done = submissions.previous_result(session, token)
    if done is None:
        return None
    set_flash(session, login, _(REPEATED_FORM))
    return RedirectResponse(done, status_code=303)


def _key_page(request: Request, station: Station, key: str, *, added: bool) -> Response:
    return render(request, "stations/key.html", {"station": station, "key": key, "added": added})


# ---- the pages ------------------------------------------------------------------------------------


@router.get("/admin/stations")
def stations_page(request: Request, session: SessionDep, login: AdminLogin) -> Response:
    """Every station with its calibration, capacity and status."""
    return render(request, "stations/list.html", {"stations": list_stations(session), "today": utc_today()})


def _new_form(
    request: Request, values: dict[str, str], errors: FormErrors, token: str, status: int
) -> Response:
    return render(
        request,
        "stations/new.html",
        {"values": values, "errors": errors.messages, "form_token": token},
        status_code=status,
    )


@router.get("/admin/stations/new")
def new_station_form(request: Request, login: AdminLogin) -> Response:
    """The form to add a station."""
    return _new_form(request, {}, FormErrors(), submissions.new_form_token(), 200)


@router.post("/admin/stations/new")
def add_station(request: Request, session: SessionDep, login: AdminPost, form: FormDep) -> Response:
    """Add the station and show its key once; or show the form again with the problems."""
    token = _token(form)
    if token is not None and (done := _repeated(session, login, token)) is not None:
        return done
    parsed = read_station_form(form)
    if not parsed.errors:
        if token is not None:  # committed with the station, by create_station
            submissions.remember(session, token=token, user_id=login.user_id, redirect_path="/admin/stations")
        try:
            station, key = create_station(session, name=parsed.name, details=parsed.details)
        except (ServiceError, IntegrityError) as error:
            session.rollback()
            if token is not None and (done := _repeated(session, login, token)) is not None:
                return done  # the same form was sent twice at once, and the other one won
            if isinstance(error, IntegrityError):
                raise
            _add_service_error(parsed.errors, error)
        else:
            return _key_page(request, station, key, added=True)
    return _new_form(request, parsed.values, parsed.errors, token or submissions.new_form_token(), 422)


def _station_page(
    request: Request,
    station: Station,
    *,
    values: dict[str, str] | None = None,
    errors: FormErrors | None = None,
    status: int = 200,
) -> Response:
    context: dict[str, Any] = {
        "station": station,
        "values": values if values is not None else form_values_of(station),
        "errors": errors.messages if errors else {},
        "rotate_token": submissions.new_form_token(),
        "lapsed": calibration_lapsed(station, utc_today()),
    }
    return render(request, "stations/edit.html", context, status_code=status)


@router.get("/admin/stations/{station_id}")
def station_page(request: Request, session: SessionDep, login: AdminLogin, station_id: StationId) -> Response:
    """A station's details to edit, and the forms to rotate its key and disable or enable it."""
    return _station_page(request, get_station(session, station_id))


@router.post("/admin/stations/{station_id}")
def edit_station(
    request: Request, session: SessionDep, login: AdminPost, form: FormDep, station_id: StationId
) -> Response:
    """Store the new details, or show the form again with the problems (nothing stored)."""
    station = get_station(session, station_id)
    parsed = read_station_form(form)
    if not parsed.errors:
        try:
            update_station(session, station=station, details=parsed.details, name=parsed.name)
        except ServiceError as error:
            session.rollback()
            _add_service_error(parsed.errors, error)
        except IntegrityError:  # another station took the name meanwhile
            session.rollback()
            parsed.errors.add(
                "name", _("A station named %(name)s already exists") % {"name": repr(parsed.name)}
            )
        else:
            set_flash(session, login, _("The details of %(name)s were saved.") % {"name": station.name})
            return RedirectResponse(f"/admin/stations/{station.id}", status_code=303)
    return _station_page(request, station, values=parsed.values, errors=parsed.errors, status=422)


@router.post("/admin/stations/{station_id}/key")
def rotate_station_key(
    request: Request, session: SessionDep, login: ConfirmedAdminPost, form: FormDep, station_id: StationId
) -> Response:
    """Give the station a new key and show it once; the old key stops working at once."""
    station = get_station(session, station_id)
    token = _token(form)
    if token is not None:
        if (done := _repeated(session, login, token)) is not None:
            return done
        # Committed together with the new key by rotate_key: a second submission cannot rotate again.
        submissions.remember(
            session, token=token, user_id=login.user_id, redirect_path=f"/admin/stations/{station.id}"
        )
    try:
        key = rotate_key(session, station=station)
    except IntegrityError:
        session.rollback()
        if token is not None and (done := _repeated(session, login, token)) is not None:
            return done
        raise
    return _key_page(request, station, key, added=False)


def _set_active(session: Session, login: UserSession, station_id: int, active: bool) -> Response:
    station = set_station_active(session, station=get_station(session, station_id), active=active)
    if active:
        message = _("%(name)s is enabled: its key works again.") % {"name": station.name}
    else:
        message = _("%(name)s is disabled: its key is refused until the station is enabled.") % {
            "name": station.name
        }
    set_flash(session, login, message)
    return RedirectResponse(f"/admin/stations/{station.id}", status_code=303)


@router.post("/admin/stations/{station_id}/disable")
def disable_station(session: SessionDep, login: AdminPost, station_id: StationId) -> Response:
    """Refuse the station's key (401) until it is enabled again."""
    return _set_active(session, login, station_id, active=False)


@router.post("/admin/stations/{station_id}/enable")
def enable_station(session: SessionDep, login: AdminPost, station_id: StationId) -> Response:
    """Accept the station's key again."""
    return _set_active(session, login, station_id, active=True)


# ---- the settings in force ------------------------------------------------------------------------


@dataclass(frozen=True)
class SettingRow:
    """One setting as the page shows it."""

    label: str
    variable: str
    value: str
    default: bool
    meaning: str


# Only these are shown, by name: a setting added later (a secret, say) never appears by accident.
# The label and meaning are marked here and translated when the page is drawn.
SHOWN_SETTINGS: tuple[tuple[str, str, str, str], ...] = (
    (
        "occupant_mass_kg",
        N_("Occupant mass"),
        "kg",
        N_("The mass of each occupant added in the loading cases."),
    ),
    (
        "sum_tolerance",
        N_("Sum tolerance"),
        "ratio",
        N_("How far the three wheel readings may disagree with the overall weight."),
    ),
    (
        "max_reading_spread_kg",
        N_("Largest spread of repeated readings"),
        "kg",
        N_("Repeated readings of one wheel that spread more (or more than one scale division) are refused."),
    ),
    (
        "require_calibration",
        N_("Calibration required"),
        "bool",
        N_(
            "Whether a station with no calibration on record is refused, and no certificate or refusal "
            "is issued for a weighing without one."
        ),
    ),
    (
        "certificate_validity_months",
        N_("Certificate validity"),
        "months",
        N_("How long a Lateral Stability Certificate is valid."),
    ),
    (
        "station_rate_limit",
        N_("Station rate limit"),
        "requests",
        N_("Requests per station key per window (0: off)."),
    ),
    (
        "station_rate_window_seconds",
        N_("Rate limit window"),
        "seconds",
        N_("The window of the station rate limit."),
    ),
    (
        "session_idle_minutes",
        N_("Session idle timeout"),
        "minutes",
        N_("An officer is signed out after this idle."),
    ),
    (
        "session_absolute_hours",
        N_("Session absolute timeout"),
        "hours",
        N_("An officer is signed out this long after signing in, however active."),
    ),
    (
        "login_max_failures",
        N_("Failed sign-ins before lock-out"),
        "count",
        N_("Failed sign-ins for one email before sign-in is refused."),
    ),
    (
        "login_lockout_minutes",
        N_("Lock-out period"),
        "minutes",
        N_("How long failed sign-ins are counted and held."),
    ),
    (
        "idempotency_key_hours",
        N_("Idempotency keys kept"),
        "hours",
        N_("How long a station's Idempotency-Key replays its first answer."),
    ),
    (
        "display_timezone",
        N_("Display time zone"),
        "text",
        N_("Times on the pages, and “today”, are in this zone."),
    ),
    (
        "mfa",
        N_("Second factor at sign-in"),
        "text",
        # Translators: “required” and “optional” are the values typed in the environment: keep them.
        N_(
            "“required”: every officer signs in with a code from an authenticator app as well as the "
            "password; “optional”: only those who set one up. Unset, it is required in production."
        ),
    ),
    (
        "base_url",
        N_("Public address"),
        "text",
        N_("Printed on every certificate and in its QR code: where anyone checks a document."),
    ),
    (
        "issuing_authority",
        N_("Issuing authority"),
        "text",
        N_("The authority named on every page and document."),
    ),
    (
        "ballast_x_m",
        N_("Ballast position"),
        "m",
        N_("Where the remedies place front ballast unless asked otherwise, behind the front wheel centre."),
    ),
    (
        "min_rollover_g",
        N_("Minimum rollover threshold"),
        "g",
        N_("Drawn on the stability map: a case below it tips too easily (an estimate; never the verdict)."),
    ),
    ("air_density_kg_m3", N_("Air density"), "kg/m³", N_("For the drag in the critical speed estimate.")),
)


def _counted(unit: str, count: int) -> str | None:
    """A count of a unit that is a word ('12 months', '1 hour'), in the active language; None otherwise."""
    if unit == "months":
        return ngettext("%(count)s month", "%(count)s months", count) % {"count": count}
    if unit == "requests":
        return ngettext("%(count)s request", "%(count)s requests", count) % {"count": count}
    if unit == "seconds":
        return ngettext("%(count)s second", "%(count)s seconds", count) % {"count": count}
    if unit == "minutes":
        return ngettext("%(count)s minute", "%(count)s minutes", count) % {"count": count}
    if unit == "hours":
        return ngettext("%(count)s hour", "%(count)s hours", count) % {"count": count}
    return None


def _shown(value: object, unit: str) -> str:
    if isinstance(value, bool):
        return _("Yes") if value else _("No")
    if isinstance(value, int) and (counted := _counted(unit, value)) is not None:
        return counted
    if unit == "ratio" and isinstance(value, Decimal):
        return f"{value.normalize():f} ({value * 100:.1f} %)"
    if isinstance(value, Decimal):
        value = f"{value.normalize():f}"
    # Text settings (a time zone, an address, the mfa mode) are shown as set in the environment.
    return f"{value} {unit}" if unit not in ("text", "count") else str(value)


def settings_rows(settings: Settings) -> list[SettingRow]:
    """The settings that matter to officers and regulators, with their environment variables."""
    fields = type(settings).model_fields
    rows = []
    for name, label, unit, meaning in SHOWN_SETTINGS:
        value = getattr(settings, name)
        shown: str
        if name == "mfa":
            shown = settings.mfa_mode()  # unset: required in production, optional elsewhere
        else:
            shown = _("Not set") if value is None else _shown(value, unit)
        rows.append(
            SettingRow(
                label=_(label),
                variable=f"TRIKECERT_{name.upper()}",
                value=shown,
                default=value == fields[name].default,
                meaning=_(meaning),
            )
        )
    return rows


@router.get("/admin/settings")
def settings_page(request: Request, login: AdminLogin) -> Response:
    """The settings in force (read only; they are changed in the environment and need a restart)."""
    settings = get_settings()
    return render(
        request,
        "stations/settings.html",
        {"rows": settings_rows(settings), "environment": settings.environment},
    )
