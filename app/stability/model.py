"""Value objects of the stability core: readings, seats, rules, loading cases, assessments."""

from __future__ import annotations

from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from functools import cached_property
from typing import Literal

from app.stability.layout import DELTA, LAYOUTS, Layout

# The study's standard for its delta keke: the vehicle understeers when LSF < 2/3. Other layouts have
# their own limit (`Layout.limit`, reference section 9).
LSF_LIMIT = DELTA.limit

Wheel = Literal[
    "front_kg", "left_rear_kg", "right_rear_kg", "overall_kg", "left_front_kg", "right_front_kg", "rear_kg"
]
# The delta's wheels and the overall weight (the study's readings); `Layout.wheels` for any layout.
WHEELS: tuple[Wheel, ...] = ("front_kg", "left_rear_kg", "right_rear_kg", "overall_kg")
SeatRole = Literal["driver", "passenger"]


@dataclass(frozen=True)
class Rules:
    """The settings in force for one assessment: occupant mass, sum tolerance and plausibility bounds."""

    occupant_mass_kg: Decimal = Decimal("72")
    sum_tolerance: Decimal = Decimal("0.01")  # allowed |a+b+c - W| as a fraction of W
    max_wheel_kg: Decimal = Decimal("1500")
    max_overall_kg: Decimal = Decimal("3000")
    min_wheelbase_m: Decimal = Decimal("1.0")
    max_wheelbase_m: Decimal = Decimal("4.0")
    min_occupant_mass_kg: Decimal = Decimal("20")
    max_occupant_mass_kg: Decimal = Decimal("250")
    max_load_item_kg: Decimal = Decimal("1000")
    max_readings_per_wheel: int = 20
    max_seats: int = 12
    seat_reach_m: Decimal = Decimal("1.0")  # how far a seat may sit outside the wheelbase span
    max_reading_decimals: int = 3
    max_distance_decimals: int = 4


@dataclass(frozen=True)
class WheelReadings:
    """Raw weighbridge readings of one weighing, each wheel read one or more times (kg).

    A wheel the vehicle's layout does not have is left empty (the core refuses it otherwise).
    """

    front_kg: tuple[Decimal, ...] = ()
    left_rear_kg: tuple[Decimal, ...] = ()
    right_rear_kg: tuple[Decimal, ...] = ()
    overall_kg: tuple[Decimal, ...] = ()
    left_front_kg: tuple[Decimal, ...] = ()
    right_front_kg: tuple[Decimal, ...] = ()
    rear_kg: tuple[Decimal, ...] = ()

    def values(self, wheel: Wheel | str) -> tuple[Decimal, ...]:
        """The raw readings of one wheel (or of the overall weight)."""
        result: tuple[Decimal, ...] = getattr(self, wheel)
        return result


@dataclass(frozen=True)
class Seat:
    """A seated occupant position, `x_m` metres behind the front wheel centre."""

    role: SeatRole
    x_m: Decimal


@dataclass(frozen=True)
class LoadItem:
    """An extra mass carried in every loading case (luggage, cargo, a fitted tank)."""

    mass_kg: Decimal
    x_m: Decimal
    label: str = "load"


@dataclass(frozen=True)
class MeasuredCase:
    """A loading case weighed directly with `occupants` persons (or ballast) aboard."""

    occupants: int
    readings: WheelReadings


@dataclass(frozen=True)
class AssessmentInput:
    """Everything one assessment needs: the empty-vehicle readings, geometry and occupants."""

    readings: WheelReadings
    wheelbase_m: Decimal
    seats: tuple[Seat, ...]
    load_items: tuple[LoadItem, ...] = ()
    measured_cases: tuple[MeasuredCase, ...] = ()
    occupant_mass_kg: Decimal | None = None  # None: the rules' standard occupant mass
    layout: Layout = DELTA


@dataclass(frozen=True)
class AveragedReadings:
    """The mean of each wheel's readings (`means`, the layout's wheels), and the overall weight used."""

    means: dict[str, Fraction]
    overall_kg: Fraction | None
    spread_kg: dict[str, Fraction] = field(default_factory=dict)
    layout: Layout = DELTA

    def mean(self, wheel: str) -> Fraction:
        """The mean reading of one of the layout's wheels."""
        return self.means[wheel]

    @property
    def front_kg(self) -> Fraction:
        """Load on the front axle: the front wheel of a delta, both front wheels otherwise."""
        return sum((self.means[w] for w in self.layout.front_wheels), Fraction(0))

    @property
    def rear_kg(self) -> Fraction:
        """Load on the rear axle: b + c on a delta, the one rear wheel of a tadpole."""
        return sum((self.means[w] for w in self.layout.rear_wheels), Fraction(0))

    @property
    def left_rear_kg(self) -> Fraction:
        """The left rear wheel's mean (a delta's or a quadricycle's)."""
        return self.means["left_rear_kg"]

    @property
    def right_rear_kg(self) -> Fraction:
        """The right rear wheel's mean (a delta's or a quadricycle's)."""
        return self.means["right_rear_kg"]

    @property
    def wheel_sum_kg(self) -> Fraction:
        """Every wheel's mean added up: a + b + c on a delta."""
        return self.front_kg + self.rear_kg

    @property
    def total_kg(self) -> Fraction:
        """The vehicle's weight: the overall reading when taken, else the wheel sum."""
        return self.overall_kg if self.overall_kg is not None else self.wheel_sum_kg


@dataclass(frozen=True)
class LoadingCase:
    """One row of the study's Table 4, in exact arithmetic."""

    occupants: int
    total_kg: Fraction
    rear_kg: Fraction
    measured: bool = False
    layout: Layout = DELTA

    @property
    def limit(self) -> Fraction:
        """The layout's exact limit of the LSF (2/3 for the delta)."""
        return self.layout.limit

    @property
    def front_kg(self) -> Fraction:
        """Load on the front axle."""
        return self.total_kg - self.rear_kg

    # Computed once per case (a frozen dataclass keeps cached properties in its __dict__): the
    # verdict, the variance and the stored figures all read the same exact fraction.
    @cached_property
    def lsf(self) -> Fraction:
        """Lateral Stability Factor: the share of the weight on the rear axle."""
        return self.rear_kg / self.total_kg

    @property
    def variance(self) -> Fraction:
        """limit - LSF (2/3 - LSF on a delta): positive is margin, negative is excess."""
        return self.layout.limit - self.lsf

    @cached_property
    def compliant(self) -> bool:
        """C when LSF < the layout's limit strictly; exactly at the limit is NC."""
        return self.lsf < self.layout.limit


@dataclass(frozen=True)
class Assessment:
    """The outcome of one inspection: every loading case and the overall verdict."""

    readings: AveragedReadings
    wheelbase_m: Decimal
    occupant_mass_kg: Decimal
    cases: tuple[LoadingCase, ...]

    @property
    def layout(self) -> Layout:
        """The vehicle's axle layout, which gives the limit."""
        return self.readings.layout

    @property
    def compliant(self) -> bool:
        """Compliant only if every loading case complies, as the study recommends."""
        return all(case.compliant for case in self.cases)

    @property
    def max_compliant_occupants(self) -> int:
        """Largest k such that the cases with 1..k occupants all comply; 0 if the driver alone fails."""
        best = 0
        for case in self.cases:
            if case.occupants == 0:
                continue
            if not case.compliant:
                break
            best = case.occupants
        return best

    @property
    def cg_from_front_m(self) -> Fraction:
        """The vehicle's own centre of gravity behind the front wheel centre, WB * R / W (no load items)."""
        return Fraction(self.wheelbase_m) * self.readings.rear_kg / self.readings.total_kg


def rules_version(layout: Layout) -> str:
    """The rules decided under, stored with every inspection: the layout's limit is part of it."""
    return f"lsf<{layout.limit_text}:cumulative-cases:v1"


# Stored with every inspection, so a later change of the rules never rewrites a past result.
RULES_VERSION = rules_version(DELTA)


def layout_of_rules(version: str) -> Layout:
    """The layout whose limit a rules version names (a type's version starts with one); else the delta."""
    for layout in LAYOUTS.values():
        if version.startswith(f"lsf<{layout.limit_text}:"):
            return layout
    return DELTA


def case_label(occupants: int) -> str:
    """The study's name of a loading case: None, Driver, Driver + 1 passenger, ..."""
    if occupants == 0:
        return "None"
    if occupants == 1:
        return "Driver"
    passengers = occupants - 1
    return f"Driver + {passengers} passenger{'s' if passengers > 1 else ''}"
