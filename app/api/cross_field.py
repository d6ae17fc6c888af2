"""Rules that relate several values, which JSON Schema cannot state, written into the operation's
description in the OpenAPI schema so that a client generated from it is not surprised.

Each schema-valid request the API still refuses is refused by one of these (a 422 whose `rule` is
named here); tests/api/test_schemathesis.py excuses a refusal only when its rule is documented here
for the operation and the request really breaks it.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import TypeVar

from app.stability import Rules

_RULES = Rules()
_REACH = f"{_RULES.seat_reach_m} m"
_Handler = TypeVar("_Handler", bound=Callable[..., object])

WORDS = {
    "sum_tolerance": "`readings.overall_kg` (and each measured case's) must agree with the sum of the "
    "wheels within `TRIKECERT_SUM_TOLERANCE` (1 % by default) of the overall weight.",
    "range": "a seat or load position (`x_m`) may lie at most "
    f"{_REACH} behind the rear axle: the body's `wheelbase_m`, else the vehicle's, bounds it; a measured "
    "case's `occupants` is at most the number of seats.",
    "missing": "the readings (and each measured case's) give every wheel of the vehicle's axle layout: a "
    "delta's `front_kg`, `left_rear_kg`, `right_rear_kg`; a tadpole's `left_front_kg`, `right_front_kg`, "
    "`rear_kg`; a quadricycle's `left_front_kg`, `right_front_kg`, `left_rear_kg`, `right_rear_kg`.",
    "extra_forbidden": "a reading of a wheel the vehicle's axle layout does not have is refused, naming "
    "the layout.",
    "duplicate": "each occupant count is measured at most once in `measured_cases`.",
    "spread": "repeated readings of one wheel may differ by at most `TRIKECERT_MAX_READING_SPREAD_KG` "
    "(2 kg by default): the scale had not settled.",
    "front_wheel_lift": "a loading case whose moments (readings, seat positions, occupant mass and "
    "wheelbase together) would lift the front wheel off the ground is refused, naming the seat.",
    "rear_wheel_lift": "the same for the rear wheels.",
    "less_than_level": "`cg_lift.front_kg` (the front raised) must be below `readings.front_kg` (level).",
    "below_wheelbase": "`cg_lift.lift_height_m` must be below the wheelbase.",
    "one_of": "give `cg_lift` or `cg_height_m`, not both.",
    "front_track": "`front_track_m` is the track of two front wheels (a tadpole, a quadricycle): a "
    "vehicle with one front wheel (a delta) has none, and giving one is refused.",
    "too_few": "a type is assessed from at least two vehicles of the make and model on file.",
    "same_model": "each inspection in `inspection_ids` is of a vehicle of that make and model (and year).",
    "one_per_vehicle": "one inspection per vehicle: two ids of the same vehicle's inspections are refused.",
    "same_layout": "the vehicles share one seat layout, wheelbase and occupant mass.",
    "measured_cases": "the inspections' loading cases are computed, not weighed with people aboard.",
    "remedies_range": "`target_occupants` is at most the inspection's seats, and `ballast_x_m` lies at "
    f"most {_REACH} behind its rear axle.",
}


def cross_field_rules(*rules: str) -> Callable[[_Handler], _Handler]:
    """Append the named rules, in words, to the handler's docstring (FastAPI's operation description)."""

    def document(handler: _Handler) -> _Handler:
        lines = [
            inspect.cleandoc(handler.__doc__ or ""),
            "",
            "Rules that relate several values (JSON Schema cannot state them); a request that breaks one "
            "is a 422 whose `errors[].rule` is:",
            "",
        ]
        for rule in rules:
            name = "range" if rule == "remedies_range" else rule
            lines.append(f"- `{name}`: {WORDS[rule]}")
        handler.__doc__ = "\n".join(lines)
        return handler

    return document
