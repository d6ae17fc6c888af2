"""An inspection as it is stored: the core's exact result rounded once, into the rows written for good.

The answer to a submission and every later reading of the inspection are built from these same
rounded values, so the station's answer and a GET of the stored inspection can never disagree.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import date, datetime
from decimal import ROUND_HALF_UP, Decimal
from fractions import Fraction
from typing import Any

from app.inspections.models import Inspection
from app.stability import (
    Assessment,
    AssessmentInput,
    Layout,
    LoadItem,
    Rules,
    WheelReadings,
    layout_named,
    rules_version,
)
from app.stability.layout import ALL_WHEELS, OVERALL
from app.stability.model import MeasuredCase

# The readings' order as stored and read back (by wheel name): the delta's as it always was.
STORED_ORDER = tuple(sorted((*ALL_WHEELS, OVERALL)))


def quantize(value: Fraction, places: int) -> Decimal:
    """An exact fraction rounded half-even to `places` decimals, for storage and display only.

    Rounded once, on the exact value, in integers (as `round` of a Fraction does, without making a
    Fraction per step), never through a Decimal division that would round to 28 digits first.
    """
    units, remainder = divmod(value.numerator * 10**places, value.denominator)
    if 2 * remainder > value.denominator or (2 * remainder == value.denominator and units % 2):
        units += 1  # past the half, or on it with an odd last digit: half-even
    return Decimal(units).scaleb(-places)


def at_scale(value: Decimal, places: int) -> Decimal:
    """A value at its column's scale, as the database gives it back (NUMERIC rounds half away from zero)."""
    return Decimal(value).quantize(Decimal(1).scaleb(-places), ROUND_HALF_UP)


@dataclass(frozen=True)
class ReadingRow:
    """A raw scale value: a wheel (or the overall weight) of the base weighing (case 0) or a measured case."""

    case_occupants: int
    wheel: str
    sequence: int
    value_kg: Decimal


@dataclass(frozen=True)
class CaseRow:
    """One row of Table 4 as stored: figures rounded to 6 (kg) and 8 (ratios) places, the verdict exact."""

    occupants: int
    total_kg: Decimal
    rear_kg: Decimal
    lsf: Decimal
    variance: Decimal
    compliant: bool
    measured: bool
    lsf_exact: str  # "p/q", so the stored verdict can be re-checked exactly


@dataclass(frozen=True)
class InspectionRecord:
    """Every stored value of one inspection, with the names its answer shows (`id` 0 until stored)."""

    id: int
    registration_number: str
    station_name: str | None
    vehicle_id: int
    station_id: int | None
    user_id: int | None
    created_at: datetime
    wheelbase_m: Decimal
    occupant_mass_kg: Decimal
    sum_tolerance: Decimal
    rules_version: str
    occupant_config: dict[str, Any]
    # Each wheel's mean; None for a wheel the layout does not have (the other layouts' at the end).
    front_kg: Decimal | None
    left_rear_kg: Decimal | None
    right_rear_kg: Decimal | None
    overall_kg: Decimal | None
    cg_from_front_m: Decimal
    compliant: bool
    max_compliant_occupants: int
    calibration_certificate: str | None
    calibration_valid_until: date | None
    dynamics_revision_id: int | None
    dynamics_input: dict[str, Any] | None
    readings: tuple[ReadingRow, ...]
    cases: tuple[CaseRow, ...]
    layout: str = "delta"
    left_front_kg: Decimal | None = None
    right_front_kg: Decimal | None = None
    rear_kg: Decimal | None = None

    @property
    def axles(self) -> Layout:
        """The axle layout the inspection was assessed under."""
        return layout_named(self.layout)

    def wheel_means(self) -> dict[str, Decimal]:
        """The layout's wheels and their stored means, front first."""
        return {wheel: getattr(self, wheel) for wheel in self.axles.wheels}

    @property
    def rear_axle_kg(self) -> Decimal:
        """The rear axle's load: the rear wheels' means added up."""
        return sum((getattr(self, wheel) for wheel in self.axles.rear_wheels), Decimal(0))

    def columns(self) -> dict[str, Any]:
        """The inspection row's columns (without its id), as the store writes them."""
        return {name: getattr(self, name) for name in INSPECTION_COLUMNS}


# The inspection table's columns the record carries, in the order the store writes them.
INSPECTION_COLUMNS = (
    "vehicle_id",
    "registration_number",
    "station_id",
    "user_id",
    "created_at",
    "wheelbase_m",
    "occupant_mass_kg",
    "sum_tolerance",
    "rules_version",
    "occupant_config",
    "layout",
    "front_kg",
    "left_rear_kg",
    "right_rear_kg",
    "left_front_kg",
    "right_front_kg",
    "rear_kg",
    "overall_kg",
    "cg_from_front_m",
    "compliant",
    "max_compliant_occupants",
    "calibration_certificate",
    "calibration_valid_until",
    "dynamics_revision_id",
    "dynamics_input",
)


@dataclass(frozen=True)
class Provenance:
    """Who and what the record names: the vehicle, the station (and its scale's calibration), the officer."""

    vehicle_id: int
    registration_number: str
    station_id: int | None = None
    station_name: str | None = None
    calibration_certificate: str | None = None
    calibration_valid_until: date | None = None
    user_id: int | None = None


def new_record(
    *,
    data: AssessmentInput,
    result: Assessment,
    rules: Rules,
    provenance: Provenance,
    measured_cases: tuple[MeasuredCase, ...],
    load_items: tuple[LoadItem, ...],
    dynamics_revision_id: int | None,
    dynamics_input: dict[str, Any],
    created_at: datetime,
) -> InspectionRecord:
    """The record of a decided inspection: every value rounded once, as it will be stored."""
    readings = result.readings
    return InspectionRecord(
        id=0,
        registration_number=provenance.registration_number,
        station_name=provenance.station_name,
        vehicle_id=provenance.vehicle_id,
        station_id=provenance.station_id,
        user_id=provenance.user_id,
        created_at=created_at,
        wheelbase_m=at_scale(result.wheelbase_m, 4),
        occupant_mass_kg=at_scale(result.occupant_mass_kg, 3),
        sum_tolerance=at_scale(rules.sum_tolerance, 4),
        rules_version=rules_version(result.layout),
        occupant_config={
            "seats": [{"role": s.role, "x_m": str(s.x_m)} for s in data.seats],
            "load_items": [
                {"label": i.label, "mass_kg": str(i.mass_kg), "x_m": str(i.x_m)} for i in load_items
            ],
        },
        layout=result.layout.name,
        **{
            wheel: quantize(readings.mean(wheel), 4) if wheel in readings.means else None
            for wheel in ALL_WHEELS
        },
        overall_kg=None if readings.overall_kg is None else quantize(readings.overall_kg, 4),
        cg_from_front_m=quantize(result.cg_from_front_m, 5),
        compliant=result.compliant,
        max_compliant_occupants=result.max_compliant_occupants,
        calibration_certificate=provenance.calibration_certificate,
        calibration_valid_until=provenance.calibration_valid_until,
        dynamics_revision_id=dynamics_revision_id,
        dynamics_input=dynamics_input,
        readings=reading_rows(data.readings, measured_cases),
        cases=case_rows(result),
    )


def reading_rows(readings: WheelReadings, measured_cases: tuple[MeasuredCase, ...]) -> tuple[ReadingRow, ...]:
    """Every raw reading as a row, in the stored order: by case (the base weighing is 0), wheel, sequence."""
    sets = sorted([(0, readings)] + [(m.occupants, m.readings) for m in measured_cases], key=lambda s: s[0])
    return tuple(
        ReadingRow(case_occupants, wheel, sequence, at_scale(value, 3))
        for case_occupants, weighing in sets
        for wheel in STORED_ORDER
        for sequence, value in enumerate(weighing.values(wheel))
    )


def case_rows(result: Assessment) -> tuple[CaseRow, ...]:
    """Table 4 as rows: each loading case's exact values rounded for storage, and its exact LSF."""
    rows = []
    for case in result.cases:
        lsf = case.lsf
        rows.append(
            CaseRow(
                occupants=case.occupants,
                total_kg=quantize(case.total_kg, 6),
                rear_kg=quantize(case.rear_kg, 6),
                lsf=quantize(lsf, 8),
                variance=quantize(case.variance, 8),
                compliant=case.compliant,
                measured=case.measured,
                lsf_exact=f"{lsf.numerator}/{lsf.denominator}",
            )
        )
    return tuple(rows)


def record_of(inspection: Inspection) -> InspectionRecord:
    """The record of an inspection read back from the database."""
    return InspectionRecord(
        id=inspection.id,
        station_name=inspection.station.name if inspection.station else None,
        **{name: getattr(inspection, name) for name in INSPECTION_COLUMNS},
        readings=tuple(
            ReadingRow(r.case_occupants, r.wheel, r.sequence, r.value_kg) for r in inspection.readings
        ),
        cases=tuple(
            CaseRow(
                c.occupants, c.total_kg, c.rear_kg, c.lsf, c.variance, c.compliant, c.measured, c.lsf_exact
            )
            for c in inspection.loading_cases
        ),
    )
