"""The new-inspection form's optional axle-lift weighing (for the estimates): its inputs and parsing."""

from __future__ import annotations

from decimal import Decimal
from typing import Protocol

from app.dynamics.estimates import CgLift
from app.i18n.active import gettext as _
from app.web.forms import FormErrors, parse_decimal

LIFT_READINGS = 3
LIFT_HEIGHT = "cg_lift_height_m"


def lift_reading_id(index: int) -> str:
    """The input id of one raised front reading: cg_front_kg_1 ... cg_front_kg_3."""
    return f"cg_front_kg_{index}"


LIFT_FIELDS = [LIFT_HEIGHT, *(lift_reading_id(i) for i in range(1, LIFT_READINGS + 1))]


class _Form(Protocol):
    values: dict[str, str]
    errors: FormErrors
    input_for: dict[str, str]


def read_lift(form: _Form) -> CgLift | None:
    """The axle-lift weighing when any of its boxes is filled (both parts are then needed), else None."""
    form.input_for.update({"cg_lift.lift_height_m": LIFT_HEIGHT, "cg_lift.front_kg": lift_reading_id(1)})
    if not any(form.values.get(name) for name in LIFT_FIELDS):
        return None
    height = _parsed(
        form,
        LIFT_HEIGHT,
        _("Enter how far the front wheel was raised as a number of metres, like %(example)s")
        % {"example": "0.40"},
    )
    readings: list[Decimal] = []
    for index in range(1, LIFT_READINGS + 1):
        box = lift_reading_id(index)
        value = _parsed(
            form,
            box,
            _("Enter the raised front wheel reaction as a number of kilograms, like %(example)s")
            % {"example": "94.8"},
        )
        if value is not None:
            form.input_for[f"cg_lift.front_kg[{len(readings)}]"] = box
            readings.append(value)
    if height is None and LIFT_HEIGHT not in form.errors.messages:
        form.errors.add(
            LIFT_HEIGHT,
            _("Enter how far the front wheel was raised, in metres, or clear the raised readings"),
        )
    if not readings and lift_reading_id(1) not in form.errors.messages:
        form.errors.add(
            lift_reading_id(1), _("Enter the front wheel reaction with the wheel raised, in kilograms")
        )
    if height is None or not readings:
        return None
    return CgLift(height, tuple(readings))


def _parsed(form: _Form, name: str, message: str) -> Decimal | None:
    raw = form.values.get(name, "")
    value = parse_decimal(raw) if raw else None
    if raw and value is None:
        form.errors.add(name, message)
    return value
