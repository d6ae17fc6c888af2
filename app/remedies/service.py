"""An inspection's remedies: its loading cases rebuilt exactly from the stored readings, then sized."""

from __future__ import annotations

from collections import defaultdict
from decimal import Decimal
from fractions import Fraction

from app.inspections.models import Inspection
from app.inspections.service import refusal
from app.stability import (
    Assessment,
    AssessmentInput,
    LoadItem,
    MeasuredCase,
    Rules,
    Seat,
    StabilityError,
    WheelReadings,
    assess,
    layout_named,
)
from app.stability.layout import ALL_WHEELS, OVERALL
from app.stability.remedies import Remedies, size_remedies


def stored_readings(inspection: Inspection, case_occupants: int) -> WheelReadings:
    """The raw readings of one weighing of a stored inspection (0: the base weighing)."""
    values: dict[str, list[Decimal]] = defaultdict(list)
    for reading in inspection.readings:  # ordered by case, wheel and sequence
        if reading.case_occupants == case_occupants:
            values[reading.wheel].append(reading.value_kg)
    return WheelReadings(**{wheel: tuple(values[wheel]) for wheel in (*ALL_WHEELS, OVERALL)})


def stored_assessment(inspection: Inspection) -> Assessment:
    """The inspection's assessment recomputed exactly from what was stored, checked against the stored LSFs.

    Readings, seats, load items, wheelbase and occupant mass are kept at the precision they were
    accepted at, so the recomputation is exact; the stored verdicts are never changed by it.
    """
    config = inspection.occupant_config
    measured = sorted({r.case_occupants for r in inspection.readings} - {0})
    data = AssessmentInput(
        readings=stored_readings(inspection, 0),
        wheelbase_m=inspection.wheelbase_m,
        seats=tuple(Seat(s["role"], Decimal(s["x_m"])) for s in config["seats"]),
        load_items=tuple(
            LoadItem(Decimal(i["mass_kg"]), Decimal(i["x_m"]), i["label"]) for i in config["load_items"]
        ),
        measured_cases=tuple(MeasuredCase(n, stored_readings(inspection, n)) for n in measured),
        occupant_mass_kg=inspection.occupant_mass_kg,
        layout=layout_named(inspection.layout),
    )
    # The tolerance in force then; the plausibility bounds are the core's, under which it was accepted.
    result = assess(
        data, Rules(occupant_mass_kg=inspection.occupant_mass_kg, sum_tolerance=inspection.sum_tolerance)
    )
    stored = [Fraction(case.lsf_exact) for case in inspection.loading_cases]
    if [case.lsf for case in result.cases] != stored:
        raise RuntimeError(
            f"inspection {inspection.id}: the recomputed loading cases differ from the stored ones"
        )
    return result


def inspection_remedies(
    inspection: Inspection, *, target_occupants: int | None, ballast_x_m: Decimal, rules: Rules
) -> Remedies:
    """The sized remedies of a stored inspection; a target or a ballast position out of range is a 422."""
    try:
        return size_remedies(
            stored_assessment(inspection),
            target_occupants=target_occupants,
            ballast_x_m=ballast_x_m,
            rules=rules,
        )
    except StabilityError as error:
        raise refusal(error) from error
