"""The new-inspection form: repeated readings per wheel (blanks ignored), geometry and occupants
pre-filled from the vehicle, optional measured cases. Parsing only; every rule stays in the core."""

from __future__ import annotations

from dataclasses import dataclass, field
from decimal import Decimal

from starlette.datastructures import FormData

from app.dynamics.forms import LIFT_FIELDS, read_lift
from app.i18n.active import N_, current_locale
from app.i18n.active import gettext as _
from app.i18n.locales import ENGLISH
from app.inspections.service import InspectionRequest
from app.stability import MeasuredCase, Seat, WheelReadings, layout_named
from app.stability.layout import OVERALL
from app.stability.validation import WHEEL_WORDS
from app.vehicles.models import Vehicle
from app.web.forms import FormErrors, parse_decimal, text

READINGS_PER_WHEEL = 3
WHEELS = ("front_kg", "left_rear_kg", "right_rear_kg", "overall_kg")  # the delta's


def wheels_of(vehicle: Vehicle) -> tuple[str, ...]:
    """The boxes of a vehicle's form: its layout's wheels, front first, then the overall weight."""
    return (*layout_named(vehicle.layout).wheels, OVERALL)


# A wheel's legend and hint on the form, and its short label for a measured case.
WHEEL_LABELS: dict[str, tuple[str, str, str]] = {
    "front_kg": (
        N_("Front wheel reaction (kg)"),
        N_("The weighbridge reading under the front wheel alone."),
        N_("Front wheel (kg)"),
    ),
    "left_front_kg": (
        N_("Left front wheel reaction (kg)"),
        N_("The reading under the left front wheel alone."),
        N_("Left front (kg)"),
    ),
    "right_front_kg": (
        N_("Right front wheel reaction (kg)"),
        N_("The reading under the right front wheel alone."),
        N_("Right front (kg)"),
    ),
    "left_rear_kg": (
        N_("Left rear wheel reaction (kg)"),
        N_("The reading under the left rear wheel alone."),
        N_("Left rear (kg)"),
    ),
    "right_rear_kg": (
        N_("Right rear wheel reaction (kg)"),
        N_("The reading under the right rear wheel alone."),
        N_("Right rear (kg)"),
    ),
    "rear_kg": (
        N_("Rear wheel reaction (kg)"),
        N_("The reading under the rear wheel alone."),
        N_("Rear wheel (kg)"),
    ),
    "overall_kg": (
        N_("Overall weight (kg)"),
        N_(
            "The whole empty vehicle on the weighbridge. Leave blank if it was not weighed; then the wheels’ "
            "sum is used. The wheels must add up to within %(tolerance)s of it."
        ),
        N_("Overall (kg)"),
    ),
}


def reading_id(wheel: str, index: int) -> str:
    """The input id of one reading box: front_kg_1 ... overall_kg_3."""
    return f"{wheel}_{index}"


def measured_id(occupants: int, wheel: str) -> str:
    """The input id of a measured case's reading: measured_2_front_kg."""
    return f"measured_{occupants}_{wheel}"


def seat_id(index: int) -> str:
    """The input id of a seat position: seat_x_m_0 is the driver."""
    return f"seat_x_m_{index}"


def field_names(seat_count: int, wheels: tuple[str, ...] = WHEELS) -> list[str]:
    """Every input of the form, in page order."""
    names = [reading_id(w, i) for w in wheels for i in range(1, READINGS_PER_WHEEL + 1)]
    names += ["wheelbase_m", "occupant_mass_kg"] + [seat_id(i) for i in range(seat_count)]
    names += [measured_id(n, w) for n in range(1, seat_count + 1) for w in wheels]
    return names + LIFT_FIELDS


def metres(value: Decimal) -> str:
    """A distance as an officer writes it: 2.000, 0.9303, 1.630."""
    text = f"{value:.4f}"
    return text[:-1] if text.endswith("0") else text


def initial_values(vehicle: Vehicle, occupant_mass_kg: Decimal) -> dict[str, str]:
    """The form as first shown: geometry and occupants from the vehicle and the settings."""
    values = dict.fromkeys(field_names(len(vehicle.seats), wheels_of(vehicle)), "")
    values["wheelbase_m"] = metres(vehicle.wheelbase_m)
    values["occupant_mass_kg"] = f"{occupant_mass_kg.normalize():f}"
    for i, seat in enumerate(vehicle.seats):
        values[seat_id(i)] = metres(seat.x_m)
    return values


@dataclass
class InspectionForm:
    """The parsed form, its raw values to show again, its errors and where each core field lives."""

    values: dict[str, str]
    errors: FormErrors = field(default_factory=FormErrors)
    request: InspectionRequest | None = None
    input_for: dict[str, str] = field(default_factory=dict)


def wheel_labels(wheel: str) -> tuple[str, str, str]:
    """A wheel's legend, hint and short label on the form, in the active language."""
    legend, hint, short = WHEEL_LABELS[wheel]
    # The tolerance is a figure, never translated by hand; a hint without it is unchanged by the %.
    # Held on one line with its figure (a longer sentence can wrap there), the English as it always was.
    tolerance = "1 %" if current_locale() == ENGLISH else "1\u00a0%"
    return _(legend), _(hint) % {"tolerance": tolerance}, _(short)


# What a box holds, as a refusal names it (the core's words for the wheels, marked here).
_KILOGRAMS = N_("Enter the %(what)s as a number of kilograms, like %(example)s")
_METRES = N_("Enter the %(what)s as a number of metres, like %(example)s")


def _number(form: InspectionForm, input_id: str, what: str, unit: str, example: str) -> Decimal | None:
    raw = form.values[input_id]
    value = parse_decimal(raw) if raw else None
    if raw and value is None:
        message = _KILOGRAMS if unit == "kilograms" else _METRES
        form.errors.add(input_id, _(message) % {"what": _(what), "example": example})
    return value


def _readings(form: InspectionForm, prefix: str, ids: dict[str, list[str]]) -> WheelReadings:
    """Readings from the given boxes per wheel; each core path is mapped to the box it came from."""
    found: dict[str, tuple[Decimal, ...]] = {}
    for wheel, boxes in ids.items():
        values: list[Decimal] = []
        used: list[str] = []
        for box in boxes:
            value = _number(form, box, WHEEL_WORDS[wheel], "kilograms", "108.5")
            if value is not None:
                values.append(value)
                used.append(box)
        path = f"{prefix}.{wheel}"
        form.input_for[path] = used[0] if used else boxes[0]
        for i, box in enumerate(used):
            form.input_for[f"{path}[{i}]"] = box
        found[wheel] = tuple(values)
    form.input_for.setdefault(prefix, next(iter(ids.values()))[0])
    return WheelReadings(**found)


def read_inspection_form(form_data: FormData, vehicle: Vehicle) -> InspectionForm:
    """Parse the posted form into the service's request, or collect what could not be read."""
    seat_count = len(vehicle.seats)
    wheels = wheels_of(vehicle)
    errors = FormErrors()
    values = {name: text(form_data, name, errors, limit=40) for name in field_names(seat_count, wheels)}
    form = InspectionForm(values=values, errors=errors)
    readings = _readings(
        form, "readings", {w: [reading_id(w, i) for i in range(1, READINGS_PER_WHEEL + 1)] for w in wheels}
    )
    wheelbase = _number(form, "wheelbase_m", N_("wheelbase"), "metres", "2.000")
    if wheelbase is None:
        form.errors.add("wheelbase_m", _(_METRES) % {"what": _("wheelbase"), "example": "2.000"})
    mass = _number(form, "occupant_mass_kg", N_("standard occupant mass"), "kilograms", "72")
    if mass is None:
        form.errors.add(
            "occupant_mass_kg", _(_KILOGRAMS) % {"what": _("standard occupant mass"), "example": "72"}
        )
    form.input_for.update({"wheelbase_m": "wheelbase_m", "occupants.mass_kg": "occupant_mass_kg"})

    seats: list[Seat] = []
    for i in range(seat_count):
        position = _number(form, seat_id(i), N_("seat position"), "metres", "1.630")
        if position is None and i == 0:
            form.errors.add(
                seat_id(0), _(_METRES) % {"what": _("driver's seat position"), "example": "0.930"}
            )
        if position is not None:
            form.input_for[f"occupants.seats[{len(seats)}]"] = seat_id(i)
            seats.append(Seat("driver" if i == 0 else "passenger", position))
    form.input_for["occupants.seats"] = seat_id(0)

    measured: list[MeasuredCase] = []
    for occupants in range(1, seat_count + 1):
        boxes = {w: [measured_id(occupants, w)] for w in wheels}
        if not any(form.values[b[0]] for b in boxes.values()):
            continue
        prefix = f"measured_cases[{len(measured)}]"
        form.input_for[f"{prefix}.occupants"] = boxes[wheels[0]][0]
        measured.append(MeasuredCase(occupants, _readings(form, f"{prefix}.readings", boxes)))

    cg_lift = read_lift(form, layout_named(vehicle.layout))
    if not form.errors and wheelbase is not None and mass is not None:
        form.request = InspectionRequest(
            registration_number=vehicle.registration_key,
            readings=readings,
            wheelbase_m=wheelbase,
            occupant_mass_kg=mass,
            seats=tuple(seats),
            measured_cases=tuple(measured),
            cg_lift=cg_lift,
        )
    return form
