"""Pydantic number types for the API: JSON numbers only (no strings, no booleans), finite, bounded.

The bounds come from the stability core's default Rules, so the schema and the domain agree. The
schema also states the precision the core accepts (3 decimals for kg, 4 for metres) as `multipleOf`;
JSON Schema validators test it on the number as written, as the core does on the Decimal.
"""

from __future__ import annotations

from decimal import Decimal
from typing import Annotated, Any

from pydantic import BeforeValidator, Field, WithJsonSchema
from pydantic_core import PydanticCustomError

from app.stability import Rules

LIMITS = Rules()
MAX_READINGS = LIMITS.max_readings_per_wheel
MAX_LOAD_ITEMS = 10


def _json_kind(value: Any) -> str:
    if isinstance(value, bool):
        return "true or false"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, dict):
        return "an object"
    if isinstance(value, list):
        return "a list"
    return "null" if value is None else type(value).__name__


def number_only(value: Any) -> Any:
    """Refuse strings, booleans, objects and null where a JSON number is required (rule `number_type`)."""
    if isinstance(value, bool) or not isinstance(value, int | float | Decimal):
        raise PydanticCustomError(
            "number_type", "enter a JSON number, not {kind}", {"kind": _json_kind(value)}
        )
    return value


def whole_number_only(value: Any) -> Any:
    """Refuse anything but a JSON number with no fraction (rule `int_type`); `2012.0` is 2012."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        kind = _json_kind(value) if not isinstance(value, float) else "a fraction"
        raise PydanticCustomError("int_type", "enter a whole JSON number, not {kind}", {"kind": kind})
    return value


def ascii_number_text(value: Any) -> Any:
    """A number from a query string in ASCII digits only (Decimal would read ٣ or ３ as 3): rule
    `number_format`."""
    if isinstance(value, str) and not (value.isascii() and value.strip() == value):
        raise PydanticCustomError("number_format", "write the number in the digits 0-9, like 0.30")
    return value


def one_or_many(value: Any) -> Any:
    """Accept one reading or a list of repeated readings; hand the validator a list."""
    return value if isinstance(value, list) else [value]


def number_schema(minimum: Decimal, maximum: Decimal, *, exclusive: bool, decimals: int) -> dict[str, Any]:
    """The JSON schema of a bounded number given to at most `decimals` places (as `multipleOf`)."""
    return {
        "type": "number",
        "exclusiveMinimum" if exclusive else "minimum": float(minimum),
        "maximum": float(maximum),
        "multipleOf": float(Decimal(1).scaleb(-decimals)),
    }


def readings_schema(item: dict[str, Any]) -> dict[str, Any]:
    """The JSON schema of one reading or a list of repeated readings."""
    return {
        "oneOf": [item, {"type": "array", "items": item, "minItems": 1, "maxItems": MAX_READINGS}],
        "description": "One reading in kg, or a list of repeated readings that are averaged.",
    }


KG_DECIMALS = LIMITS.max_reading_decimals
M_DECIMALS = LIMITS.max_distance_decimals
_WHEEL = number_schema(Decimal(0), LIMITS.max_wheel_kg, exclusive=True, decimals=KG_DECIMALS)
_OVERALL = number_schema(Decimal(0), LIMITS.max_overall_kg, exclusive=True, decimals=KG_DECIMALS)

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
    WithJsonSchema(
        number_schema(
            LIMITS.min_occupant_mass_kg, LIMITS.max_occupant_mass_kg, exclusive=False, decimals=KG_DECIMALS
        )
    ),
]
LoadKilograms = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(gt=0, le=LIMITS.max_load_item_kg, allow_inf_nan=False),
    WithJsonSchema(number_schema(Decimal(0), LIMITS.max_load_item_kg, exclusive=True, decimals=KG_DECIMALS)),
]
POSITION_SCHEMA = number_schema(
    -LIMITS.seat_reach_m, LIMITS.max_wheelbase_m + LIMITS.seat_reach_m, exclusive=False, decimals=M_DECIMALS
)
Position = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(ge=-LIMITS.seat_reach_m, le=LIMITS.max_wheelbase_m + LIMITS.seat_reach_m, allow_inf_nan=False),
    WithJsonSchema(POSITION_SCHEMA),
]
Wheelbase = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(ge=LIMITS.min_wheelbase_m, le=LIMITS.max_wheelbase_m, allow_inf_nan=False),
    WithJsonSchema(
        number_schema(LIMITS.min_wheelbase_m, LIMITS.max_wheelbase_m, exclusive=False, decimals=M_DECIMALS)
    ),
]
# Metadata for an `int` field of a body: `Annotated[int, Field(ge=..., le=...), WHOLE_NUMBER]`.
WHOLE_NUMBER = BeforeValidator(whole_number_only)

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
