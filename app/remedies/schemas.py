"""API shape of an inspection's remedies: each remedy over the cases up to the target, and every case."""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from app.stability import case_label
from app.stability.remedies import (
    BALLAST_STEP,
    RATIO_STEP,
    SHIFT_STEP,
    CaseRemedies,
    Remedies,
    Remedy,
    advice,
    as_decimal,
)


class BallastOut(BaseModel):
    """Front ballast at `x_m`: more than `min_mass_kg` makes every case up to the target comply."""

    x_m: float
    min_mass_kg: float | None = Field(
        description="Rounded up to 0.01 kg; null when ballast there cannot help."
    )
    binding_occupants: int | None
    possible: bool
    unfixable_occupants: list[int]


class SeatShiftOut(BaseModel):
    """Every passenger seat moved `min_forward_m` forward (the driver's stays)."""

    min_forward_m: float | None = Field(description="Rounded up to 0.001 m; null when no case can be mended.")
    binding_occupants: int | None
    possible: bool = Field(description="False when a case up to the target has no passenger to move.")
    unfixable_occupants: list[int]


class RearTyreRatioOut(BaseModel):
    """Rear tyres at least `min_ratio` times as stiff in cornering as the front tyre."""

    min_ratio: float = Field(description="CaR / CaF, rounded up to 0.001.")
    binding_occupants: int


class CaseRemediesOut(BaseModel):
    """One loading case: what it alone needs, and its LSF and verdict after each advised remedy."""

    occupants: int
    label: str
    lsf: float
    compliant: bool
    ballast_kg: float | None = Field(description="Null when the case complies or ballast there cannot help.")
    seat_shift_m: float | None = Field(description="Null when the case complies or carries no passenger.")
    tyre_ratio: float = Field(description="The CaR / CaF above which this case understeers (rounded up).")
    lsf_after_ballast: float | None = Field(description="With the advised ballast fitted, to 6 decimals.")
    compliant_after_ballast: bool | None = Field(description="Decided on the exact LSF after the ballast.")
    lsf_after_seat_shift: float | None = Field(description="With the seats moved as advised, to 6 decimals.")
    compliant_after_seat_shift: bool | None


STUDY_REMEDIES_EXAMPLE: dict[str, Any] = {
    "target_occupants": 4,
    "compliant": False,
    "max_compliant_occupants": 1,
    "ballast": {
        "x_m": 0.3,
        "min_mass_kg": 54.64,
        "binding_occupants": 4,
        "possible": True,
        "unfixable_occupants": [],
    },
    "seat_shift": {
        "min_forward_m": 0.262,
        "binding_occupants": 4,
        "possible": False,
        "unfixable_occupants": [0],
    },
    "rear_tyre_ratio": {"min_ratio": 1.226, "binding_occupants": 4},
    "cases": [
        {
            "occupants": 0,
            "label": "None",
            "lsf": 0.6964,
            "compliant": False,
            "ballast_kg": 20.65,
            "seat_shift_m": None,
            "tyre_ratio": 1.147,
            "lsf_after_ballast": 0.624205,
            "compliant_after_ballast": True,
            "lsf_after_seat_shift": 0.696379,
            "compliant_after_seat_shift": False,
        }
    ],
}


class RemediesOut(BaseModel):
    """What would make every loading case up to `target_occupants` comply; null remedies: none needed."""

    model_config = ConfigDict(json_schema_extra={"examples": [STUDY_REMEDIES_EXAMPLE]})

    target_occupants: int
    compliant: bool = Field(description="Every case up to the target already complies.")
    max_compliant_occupants: int
    ballast: BallastOut | None
    seat_shift: SeatShiftOut | None
    rear_tyre_ratio: RearTyreRatioOut | None
    cases: list[CaseRemediesOut]


def _figure(value: Fraction | None, step: Fraction) -> float | None:
    """An advised figure as a JSON number (it is already a multiple of the step)."""
    return None if value is None else float(as_decimal(value, step))


def _lsf(value: Fraction | None) -> float | None:
    # Six places: the advised remedy leaves the binding case just below 2/3, which four would round up.
    return None if value is None else float(round(value, 6))


def _case(case: CaseRemedies) -> CaseRemediesOut:
    return CaseRemediesOut(
        occupants=case.occupants,
        label=case_label(case.occupants),
        lsf=float(round(case.lsf, 4)),
        compliant=case.compliant,
        ballast_kg=_figure(
            None if case.ballast_kg is None else advice(case.ballast_kg, BALLAST_STEP), BALLAST_STEP
        ),
        seat_shift_m=_figure(
            None if case.seat_shift_m is None else advice(case.seat_shift_m, SHIFT_STEP), SHIFT_STEP
        ),
        tyre_ratio=float(as_decimal(advice(case.tyre_ratio, RATIO_STEP), RATIO_STEP)),
        lsf_after_ballast=_lsf(case.lsf_after_ballast),
        compliant_after_ballast=case.complies_after_ballast,
        lsf_after_seat_shift=_lsf(case.lsf_after_seat_shift),
        compliant_after_seat_shift=case.complies_after_seat_shift,
    )


def remedies_out(remedies: Remedies) -> RemediesOut:
    """The API view of sized remedies: advised figures rounded up, LSFs to 4 decimals, verdicts exact."""
    ballast, shift, tyres = remedies.ballast, remedies.seat_shift, remedies.rear_tyre_ratio
    return RemediesOut(
        target_occupants=remedies.target_occupants,
        compliant=remedies.compliant,
        max_compliant_occupants=remedies.max_compliant_occupants,
        ballast=None if ballast is None else _ballast(ballast, float(remedies.ballast_x_m)),
        seat_shift=None
        if shift is None
        else SeatShiftOut(
            min_forward_m=_figure(shift.advised, SHIFT_STEP),
            binding_occupants=shift.binding_occupants,
            possible=shift.possible,
            unfixable_occupants=list(shift.unfixable_occupants),
        ),
        rear_tyre_ratio=None
        if tyres is None or tyres.advised is None or tyres.binding_occupants is None
        else RearTyreRatioOut(
            min_ratio=float(as_decimal(tyres.advised, RATIO_STEP)), binding_occupants=tyres.binding_occupants
        ),
        cases=[_case(case) for case in remedies.cases],
    )


def _ballast(ballast: Remedy, x_m: float) -> BallastOut:
    return BallastOut(
        x_m=x_m,
        min_mass_kg=_figure(ballast.advised, BALLAST_STEP),
        binding_occupants=ballast.binding_occupants,
        possible=ballast.possible,
        unfixable_occupants=list(ballast.unfixable_occupants),
    )
