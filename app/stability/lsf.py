"""Loading cases and the Lateral Stability Factor, computed exactly (paper eq. 30-31, Table 4)."""

from __future__ import annotations

from collections.abc import Sequence
from decimal import Decimal
from fractions import Fraction

from app.stability.errors import StabilityError
from app.stability.layout import DELTA, OVERALL, Layout
from app.stability.model import (
    Assessment,
    AssessmentInput,
    AveragedReadings,
    LoadingCase,
    Rules,
    WheelReadings,
)
from app.stability.validation import (
    check_geometry,
    check_measured_occupants,
    check_readings,
    check_sum_tolerance,
    fmt_kg,
)


def mean(values: Sequence[Decimal]) -> Fraction:
    """The exact arithmetic mean of repeated readings."""
    return sum((Fraction(v) for v in values), Fraction(0)) / len(values)


def checked_mean(values: Sequence[Decimal]) -> Fraction:
    """The exact mean of readings that passed `check_readings` (finite, at most 3000 kg to 3 places,
    at most 20 of them): their sum has at most 8 digits, so the Decimal sum is exact, and one
    Fraction is made instead of one per reading."""
    return Fraction(sum(values, Decimal(0))) / len(values)


def average_readings(
    readings: WheelReadings, rules: Rules, *, prefix: str = "readings", layout: Layout = DELTA
) -> AveragedReadings:
    """Validate and average one weighing's readings, checking the wheel sum against the overall weight."""
    check_readings(readings, rules, prefix=prefix, layout=layout)
    overall = checked_mean(readings.overall_kg) if readings.overall_kg else None
    averaged = AveragedReadings(
        means={wheel: checked_mean(readings.values(wheel)) for wheel in layout.wheels},
        overall_kg=overall,
        spread_kg={
            wheel: Fraction(max(values) - min(values))
            for wheel in (*layout.wheels, OVERALL)
            if (values := readings.values(wheel))
        },
        layout=layout,
    )
    if overall is not None:
        check_sum_tolerance(averaged.wheel_sum_kg, overall, rules, prefix=prefix, layout=layout)
    return averaged


def assess(data: AssessmentInput, rules: Rules | None = None) -> Assessment:
    """Compute every cumulative loading case (empty, driver, driver + 1, ...) and the verdict."""
    rules = rules or Rules()
    check_geometry(data, rules)
    check_measured_occupants(data)
    return assess_averaged(average_readings(data.readings, rules, layout=data.layout), data, rules)


def assess_averaged(base: AveragedReadings, data: AssessmentInput, rules: Rules) -> Assessment:
    """The loading cases from readings already averaged (a type's mean readings); `data` gives the rest."""
    mass = data.occupant_mass_kg if data.occupant_mass_kg is not None else rules.occupant_mass_kg
    wheelbase = Fraction(data.wheelbase_m)
    layout = base.layout

    # The empty case can lift a wheel from the readings alone (W well below b + c) or from the load
    # items; name whichever is responsible, never the seats, which carry nobody in this case.
    _checked(LoadingCase(0, base.total_kg, base.rear_kg, layout=layout), "readings")
    total = base.total_kg
    rear = base.rear_kg
    for item in data.load_items:
        total += Fraction(item.mass_kg)
        rear += Fraction(item.mass_kg) * Fraction(item.x_m) / wheelbase

    measured = {m.occupants: m for m in data.measured_cases}
    cases = [_checked(LoadingCase(0, total, rear, layout=layout), "load_items")]
    occupant = Fraction(mass)
    per_metre = occupant / wheelbase
    for index, seat in enumerate(data.seats):
        occupants = index + 1
        # Moments about the front contact point: an occupant at x adds m*x/WB to the rear axle.
        total += occupant
        rear += per_metre * Fraction(seat.x_m)
        if occupants in measured:
            prefix = f"measured_cases[{data.measured_cases.index(measured[occupants])}].readings"
            weighed = average_readings(measured[occupants].readings, rules, prefix=prefix, layout=layout)
            case = LoadingCase(occupants, weighed.total_kg, weighed.rear_kg, measured=True, layout=layout)
            cases.append(_checked(case, prefix))
        else:
            case = LoadingCase(occupants, total, rear, layout=layout)
            cases.append(_checked(case, f"occupants.seats[{index}].x_m"))
    return Assessment(readings=base, wheelbase_m=data.wheelbase_m, occupant_mass_kg=mass, cases=tuple(cases))


def _checked(case: LoadingCase, field: str) -> LoadingCase:
    """Refuse a loading case that would lift the front or the rear axle off the ground."""
    if case.total_kg <= case.rear_kg:  # front_kg <= 0, without computing it
        raise StabilityError(
            field,
            "front_wheel_lift",
            f"{field}: with {case.occupants} occupant(s) the {case.layout.front_axle_words} would carry "
            f"{fmt_kg(case.front_kg)} kg and lift off the ground; check the seat positions and readings",
        )
    if case.rear_kg <= 0:
        raise StabilityError(
            field,
            "rear_wheel_lift",
            f"{field}: with {case.occupants} occupant(s) the {case.layout.rear_axle_words} would carry "
            f"{fmt_kg(case.rear_kg)} kg and lift off the ground; check the seat positions and readings",
        )
    return case
