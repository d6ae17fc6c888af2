"""The register-a-vehicle form: read and parse the fields; the rules stay in the service and core."""

from __future__ import annotations

from dataclasses import dataclass, field
from decimal import Decimal

from starlette.datastructures import FormData

from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.stability import LAYOUT_NAMES
from app.vehicles.schemas import REGISTRATION_WORDS
from app.vehicles.service import normalise_registration, valid_key
from app.web.forms import FormErrors, parse_decimal, readable, text
from app.web.refusals import translated_refusal

PASSENGER_ROWS = 6
TEXT_LIMITS = {"registration_number": 32, "make": 80, "model": 80, "chassis_number": 64}
FIELDS = (
    "registration_number",
    "layout",
    "make",
    "model",
    "model_year",
    "chassis_number",
    "wheelbase_m",
    "driver_x_m",
    *(f"passenger_x_m_{i}" for i in range(1, PASSENGER_ROWS + 1)),
)
POSITION_HINT = N_(
    "Enter the seat position as a number of metres behind the front wheel centre, like %(example)s"
)


@dataclass
class VehicleForm:
    """The typed form, its raw values (to show again) and its errors."""

    values: dict[str, str]
    errors: FormErrors = field(default_factory=FormErrors)
    wheelbase_m: Decimal | None = None
    model_year: int | None = None
    seats: list[tuple[str, Decimal]] = field(default_factory=list)
    # The service's field path of each seat -> the input that holds it.
    input_for: dict[str, str] = field(default_factory=dict)


def read_vehicle_form(form: FormData) -> VehicleForm:
    """Parse the posted form; blank passenger rows are ignored."""
    errors = FormErrors()
    values = {name: text(form, name, errors, limit=TEXT_LIMITS.get(name, 40)) for name in FIELDS}
    # The layout is a radio group: its message stands beside the group, whose first button is its id.
    errors.messages = {("layout-delta" if k == "layout" else k): v for k, v in errors.messages.items()}
    result = VehicleForm(values=values, errors=errors)
    if not values["registration_number"]:
        errors.add(
            "registration_number",
            _("Enter the registration number, like %(plate)s") % {"plate": "BDG 252 QH"},
        )
    elif not valid_key(normalise_registration(values["registration_number"])):
        # The API's rule and words, beside the field even when another field is wrong too.
        errors.add("registration_number", translated_refusal(readable(REGISTRATION_WORDS)))
    if not values["make"]:
        errors.add("make", _("Enter the make, like %(example)s") % {"example": "Bajaj"})
    if not values["model"]:
        errors.add("model", _("Enter the model, like %(example)s") % {"example": "RE 4S"})
    if values["model_year"]:
        year = values["model_year"]
        if not (year.isascii() and year.isdigit() and len(year) == 4) or not 1950 <= int(year) <= 2100:
            errors.add(
                "model_year",
                _("Enter the model year as 4 digits, like %(example)s, or leave it blank")
                % {"example": "2012"},
            )
        else:
            result.model_year = int(year)
    if not values["layout"]:
        values["layout"] = "delta"
    elif values["layout"] not in LAYOUT_NAMES:
        errors.add(
            "layout-delta", _("Choose the axle layout: %(layouts)s") % {"layouts": ", ".join(LAYOUT_NAMES)}
        )
    result.wheelbase_m = parse_decimal(values["wheelbase_m"])
    if result.wheelbase_m is None:
        errors.add(
            "wheelbase_m",
            _("Enter the %(what)s as a number of metres, like %(example)s")
            % {"what": _("wheelbase"), "example": "2.000"},
        )
    driver = parse_decimal(values["driver_x_m"])
    if driver is None:
        errors.add(
            "driver_x_m",
            _("Enter the %(what)s as a number of metres, like %(example)s")
            % {"what": _("driver's seat position"), "example": "0.930"},
        )
    else:
        result.seats.append(("driver", driver))
    result.input_for = {"seats": "driver_x_m", "seats[0]": "driver_x_m", "wheelbase_m": "wheelbase_m"}
    result.input_for["registration_number"] = "registration_number"
    result.input_for["layout"] = "layout-delta"
    for i in range(1, PASSENGER_ROWS + 1):
        name = f"passenger_x_m_{i}"
        if not values[name]:
            continue
        position = parse_decimal(values[name])
        if position is None:
            errors.add(name, _(POSITION_HINT) % {"example": "1.630"})
            continue
        result.input_for[f"seats[{len(result.seats)}]"] = name
        result.seats.append(("passenger", position))
    return result
