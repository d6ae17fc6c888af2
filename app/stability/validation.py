"""Refusals of the stability core: every implausible input is named with its rule."""

from __future__ import annotations

from collections.abc import Sequence
from decimal import Decimal
from fractions import Fraction

from app.stability.errors import StabilityError
from app.stability.layout import ALL_WHEELS, DELTA, OVERALL, Layout
from app.stability.layout import WHEEL_WORDS as WHEEL_WORDS
from app.stability.model import AssessmentInput, Rules, Seat, WheelReadings

NUMBER_WORDS = {1: "one", 2: "two", 3: "three", 4: "four"}


def fmt_kg(value: Fraction | Decimal) -> str:
    """A weight for messages: at most one decimal, no trailing zero."""
    text = f"{float(value):.1f}"
    return text[:-2] if text.endswith(".0") else text


def check_number(
    value: Decimal,
    *,
    field: str,
    minimum: Decimal,
    maximum: Decimal,
    decimals: int,
    what: str,
    unit: str,
    inclusive_minimum: bool = False,
) -> None:
    """Refuse a non-finite, out-of-range or over-precise number."""
    if not value.is_finite():
        raise StabilityError(field, "finite", f"{field}: enter the {what} as a finite number of {unit}")
    too_low = value < minimum if inclusive_minimum else value <= minimum
    if too_low or value > maximum:
        bound = "at least" if inclusive_minimum else "more than"
        raise StabilityError(
            field,
            "range",
            f"{field}: the {what} must be {bound} {minimum} and at most {maximum} {unit}; got {value}",
        )
    exponent = value.as_tuple().exponent
    if isinstance(exponent, int) and -exponent > decimals:
        raise StabilityError(
            field, "precision", f"{field}: give the {what} to at most {decimals} decimal places"
        )


def check_readings(
    readings: WheelReadings, rules: Rules, *, prefix: str = "readings", layout: Layout = DELTA
) -> None:
    """Refuse a wheel the layout lacks, and empty, non-positive, absurd or over-long reading lists."""
    for wheel in ALL_WHEELS:
        if wheel not in layout.wheels and readings.values(wheel):
            raise StabilityError(
                f"{prefix}.{wheel}",
                "not_in_layout",
                f"{prefix}.{wheel}: not a reading of a {layout.name} vehicle ({layout.description}); "
                f"give {', '.join(layout.wheels)}",
            )
    for wheel in (*layout.wheels, OVERALL):
        values = readings.values(wheel)
        field = f"{prefix}.{wheel}"
        if not values and wheel != "overall_kg":
            raise StabilityError(
                field, "required", f"{field}: give at least one reading of the {WHEEL_WORDS[wheel]}"
            )
        if len(values) > rules.max_readings_per_wheel:
            raise StabilityError(
                field,
                "too_many",
                f"{field}: at most {rules.max_readings_per_wheel} repeated readings are accepted",
            )
        maximum = rules.max_overall_kg if wheel == "overall_kg" else rules.max_wheel_kg
        for index, value in enumerate(values):
            item_field = field if len(values) == 1 else f"{field}[{index}]"
            check_number(
                value,
                field=item_field,
                minimum=Decimal(0),
                maximum=maximum,
                decimals=rules.max_reading_decimals,
                what=WHEEL_WORDS[wheel],
                unit="kg",
            )


def check_sum_tolerance(
    wheel_sum: Fraction, overall: Fraction, rules: Rules, *, prefix: str = "readings", layout: Layout = DELTA
) -> None:
    """Refuse readings whose wheel sum disagrees with the overall weight beyond the tolerance."""
    difference = abs(wheel_sum - overall)
    if difference > Fraction(rules.sum_tolerance) * overall:
        share = difference / overall * 100
        allowed = rules.sum_tolerance * 100
        raise StabilityError(
            f"{prefix}.overall_kg",
            "sum_tolerance",
            f"The {NUMBER_WORDS[len(layout.wheels)]} wheel readings add up to {fmt_kg(wheel_sum)} kg "
            "but the overall weight is "
            f"{fmt_kg(overall)} kg; the difference ({float(share):.1f} %) is more than the allowed "
            f"{allowed.normalize():f} %. Weigh the vehicle again.",
        )


def check_wheelbase(wheelbase_m: Decimal, rules: Rules) -> None:
    """Refuse a wheelbase outside the plausible range."""
    check_number(
        wheelbase_m,
        field="wheelbase_m",
        minimum=rules.min_wheelbase_m,
        maximum=rules.max_wheelbase_m,
        decimals=rules.max_distance_decimals,
        what="wheelbase",
        unit="m",
        inclusive_minimum=True,
    )


def check_geometry(data: AssessmentInput, rules: Rules) -> None:
    """Refuse an implausible wheelbase, occupant mass, seat layout or load item."""
    check_wheelbase(data.wheelbase_m, rules)
    if data.occupant_mass_kg is not None:
        check_number(
            data.occupant_mass_kg,
            field="occupants.mass_kg",
            minimum=rules.min_occupant_mass_kg,
            maximum=rules.max_occupant_mass_kg,
            decimals=rules.max_reading_decimals,
            what="standard occupant mass",
            unit="kg",
            inclusive_minimum=True,
        )
    check_seat_layout(data.seats, data.wheelbase_m, rules)
    for index, item in enumerate(data.load_items):
        check_number(
            item.mass_kg,
            field=f"load_items[{index}].mass_kg",
            minimum=Decimal(0),
            maximum=rules.max_load_item_kg,
            decimals=rules.max_reading_decimals,
            what="load item mass",
            unit="kg",
        )
        check_position(item.x_m, data.wheelbase_m, rules, field=f"load_items[{index}].x_m")


def check_seat_layout(
    seats: Sequence[Seat], wheelbase_m: Decimal, rules: Rules, *, prefix: str = "occupants.seats"
) -> None:
    """Refuse a seat layout without the driver first, with too many seats or seats out of reach."""
    if not seats:
        raise StabilityError(prefix, "required", f"{prefix}: give at least the driver's seat")
    if len(seats) > rules.max_seats:
        raise StabilityError(prefix, "too_many", f"{prefix}: at most {rules.max_seats} seats are accepted")
    for index, seat in enumerate(seats):
        expected = "driver" if index == 0 else "passenger"
        if seat.role != expected:
            raise StabilityError(
                f"{prefix}[{index}].role",
                "driver_first",
                f"{prefix}[{index}].role: the first seat must be the driver's and every "
                f"other seat a passenger's; got {seat.role!r}",
            )
        check_position(seat.x_m, wheelbase_m, rules, field=f"{prefix}[{index}].x_m")


def check_position(x_m: Decimal, wheelbase_m: Decimal, rules: Rules, *, field: str) -> None:
    """Refuse a position further than the seat reach outside the wheelbase span."""
    check_number(
        x_m,
        field=field,
        minimum=-rules.seat_reach_m,
        maximum=wheelbase_m + rules.seat_reach_m,
        decimals=rules.max_distance_decimals,
        what="distance behind the front wheel centre",
        unit="m",
        inclusive_minimum=True,
    )


def check_measured_occupants(data: AssessmentInput) -> None:
    """Refuse a measured case for an occupant count the seat layout does not have, or twice."""
    seen: set[int] = set()
    for index, measured in enumerate(data.measured_cases):
        field = f"measured_cases[{index}].occupants"
        if not 1 <= measured.occupants <= len(data.seats):
            raise StabilityError(
                field,
                "range",
                f"{field}: a measured case must have between 1 and {len(data.seats)} occupants "
                f"(the number of seats); got {measured.occupants}",
            )
        if measured.occupants in seen:
            raise StabilityError(
                field, "duplicate", f"{field}: the case with {measured.occupants} occupants is measured twice"
            )
        seen.add(measured.occupants)
