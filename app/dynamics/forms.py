"""The new-inspection form's optional axle-lift weighing (for the estimates): its inputs and parsing."""

from __future__ import annotations

from decimal import Decimal
from typing import Protocol

from app.dynamics.estimates import CgLift
from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.stability import DELTA, Layout
from app.web.forms import FormErrors, parse_decimal

LIFT_READINGS = 3
LIFT_HEIGHT = "cg_lift_height_m"


def lift_reading_id(index: int) -> str:
    """The input id of one raised front reading: cg_front_kg_1 ... cg_front_kg_3."""
    return f"cg_front_kg_{index}"


LIFT_FIELDS = [LIFT_HEIGHT, *(lift_reading_id(i) for i in range(1, LIFT_READINGS + 1))]

# What is raised and weighed again: the delta's front wheel, or two front wheels together as an axle.
ONE_FRONT = {
    "height": N_("Enter how far the front wheel was raised as a number of metres, like %(example)s"),
    "reading": N_("Enter the raised front wheel reaction as a number of kilograms, like %(example)s"),
    "no height": N_("Enter how far the front wheel was raised, in metres, or clear the raised readings"),
    "no reading": N_("Enter the front wheel reaction with the wheel raised, in kilograms"),
}
TWO_FRONT = {
    "height": N_("Enter how far the front axle was raised as a number of metres, like %(example)s"),
    "reading": N_(
        "Enter both front wheels’ reaction together, axle raised, as a number of kilograms, like %(example)s"
    ),
    "no height": N_("Enter how far the front axle was raised, in metres, or clear the raised readings"),
    "no reading": N_("Enter both front wheels’ reaction together with the axle raised, in kilograms"),
}


class _Form(Protocol):
    values: dict[str, str]
    errors: FormErrors
    input_for: dict[str, str]


def read_lift(form: _Form, layout: Layout = DELTA) -> CgLift | None:
    """The axle-lift weighing when any of its boxes is filled (both parts are then needed), else None."""
    says = TWO_FRONT if layout.n_front > 1 else ONE_FRONT
    raised_example = "352.0" if layout.n_front > 1 else "94.8"  # two wheels weigh about twice one
    form.input_for.update({"cg_lift.lift_height_m": LIFT_HEIGHT, "cg_lift.front_kg": lift_reading_id(1)})
    if not any(form.values.get(name) for name in LIFT_FIELDS):
        return None
    height = _parsed(form, LIFT_HEIGHT, _(says["height"]) % {"example": "0.40"})
    readings: list[Decimal] = []
    for index in range(1, LIFT_READINGS + 1):
        box = lift_reading_id(index)
        value = _parsed(form, box, _(says["reading"]) % {"example": raised_example})
        if value is not None:
            form.input_for[f"cg_lift.front_kg[{len(readings)}]"] = box
            readings.append(value)
    if height is None and LIFT_HEIGHT not in form.errors.messages:
        form.errors.add(LIFT_HEIGHT, _(says["no height"]))
    if not readings and lift_reading_id(1) not in form.errors.messages:
        form.errors.add(lift_reading_id(1), _(says["no reading"]))
    if height is None or not readings:
        return None
    return CgLift(height, tuple(readings))


def _parsed(form: _Form, name: str, message: str) -> Decimal | None:
    raw = form.values.get(name, "")
    value = parse_decimal(raw) if raw else None
    if raw and value is None:
        form.errors.add(name, message)
    return value
