"""Pydantic number types for the API: JSON numbers only (no strings, no booleans), finite, bounded.

The bounds come from the stability core's default Rules, so the schema and the domain agree.
"""

from __future__ import annotations

from decimal import Decimal
from typing import Annotated, Any

from pydantic import BeforeValidator, Field, WithJsonSchema

from app.stability import Rules

LIMITS = Rules()
MAX_READINGS = LIMITS.max_readings_per_wheel


def number_only(value: Any) -> Any:
    """Refuse strings and booleans where a JSON number is required."""
    if isinstance(value, bool) or not isinstance(value, int | float | Decimal):
        raise ValueError("must be a JSON number")
    return value


def one_or_many(value: Any) -> Any:
    """Accept one reading or a list of repeated readings; hand the validator a list."""
    return value if isinstance(value, list) else [value]


def number_schema(minimum: Decimal, maximum: Decimal, *, exclusive: bool) -> dict[str, Any]:
    """The JSON schema of a bounded number."""
    return {"type": "number", "exclusiveMinimum" if exclusive else "minimum": float(minimum), "maximum": float(maximum)}


def readings_schema(item: dict[str, Any]) -> dict[str, Any]:
    """The JSON schema of one reading or a list of repeated readings."""
    return {
        "oneOf": [item, {"type": "array", "items": item, "minItems": 1, "maxItems": MAX_READINGS}],
        "description": "One reading in kg, or a list of repeated readings that are averaged.",
    }


_WHEEL = number_schema(Decimal(0), LIMITS.max_wheel_kg, exclusive=True)
_OVERALL = number_schema(Decimal(0), LIMITS.max_overall_kg, exclusive=True)

Kilograms = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(gt=0, le=LIMITS.max_wheel_kg, allow_inf_nan=False),
    WithJsonSchema(_WHEEL),
]
OverallKilograms = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(gt=0, le=LIMITS.max_overall_kg, allow_inf_nan=False),
    WithJsonSchema(_OVERALL),
]
OccupantKilograms = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(ge=LIMITS.min_occupant_mass_kg, le=LIMITS.max_occupant_mass_kg, allow_inf_nan=False),
    WithJsonSchema(number_schema(LIMITS.min_occupant_mass_kg, LIMITS.max_occupant_mass_kg, exclusive=False)),
]
LoadKilograms = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(gt=0, le=LIMITS.max_load_item_kg, allow_inf_nan=False),
    WithJsonSchema(number_schema(Decimal(0), LIMITS.max_load_item_kg, exclusive=True)),
]
Position = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(ge=-LIMITS.seat_reach_m, le=LIMITS.max_wheelbase_m + LIMITS.seat_reach_m, allow_inf_nan=False),
    WithJsonSchema(
        number_schema(-LIMITS.seat_reach_m, LIMITS.max_wheelbase_m + LIMITS.seat_reach_m, exclusive=False)
    ),
]
Wheelbase = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(ge=LIMITS.min_wheelbase_m, le=LIMITS.max_wheelbase_m, allow_inf_nan=False),
    WithJsonSchema(number_schema(LIMITS.min_wheelbase_m, LIMITS.max_wheelbase_m, exclusive=False)),
]
WheelReading = Annotated[
    list[Kilograms],
    BeforeValidator(one_or_many),
    Field(min_length=1, max_length=MAX_READINGS),
    WithJsonSchema(readings_schema(_WHEEL)),
]
OverallReading = Annotated[
    list[OverallKilograms],
    BeforeValidator(one_or_many),
    Field(min_length=1, max_length=MAX_READINGS),
    WithJsonSchema(readings_schema(_OVERALL)),
]
