"""An inspection's estimates beyond the static test: checked and stored with it, computed from the record.

Estimates are floats from assumed inputs; they never change the verdict the static core decided.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from decimal import Decimal
from fractions import Fraction
from typing import Any

from app.dynamics.protocols import EstimatedInspection, WeighedCase, WeighedRecord, Weighing
from app.dynamics.service import DynamicsFigures, core_figures, revision_figures
from app.errors import InvalidInput
from app.stability import DELTA, Layout, Seat, StabilityError, layout_named
from app.stability.dynamics import (
    BOUNDS,
    AxleLift,
    CaseLoad,
    Dynamics,
    DynamicsInput,
    assess_dynamics,
)
from app.stability.validation import check_number


@dataclass(frozen=True)
class CgLift:
    """The axle-lift weighing as sent: the lift height and the raised front wheel's readings."""

    lift_height_m: Decimal
    front_kg: tuple[Decimal, ...]

    @property
    def mean_front_kg(self) -> Fraction:
        """The raised front readings averaged, exactly."""
        return sum((Fraction(v) for v in self.front_kg), Fraction(0)) / len(self.front_kg)


def estimate_inputs(
    *,
    cg_lift: CgLift | None,
    cg_height_m: Decimal | None,
    seats: Sequence[Seat] | None,
    vehicle_seats: Sequence[Seat],
    figures: DynamicsFigures,
) -> dict[str, Any]:
    """What an inspection keeps for its estimates: the CG-height weighing as sent and the seat heights used.

    The weighing is refused (422 naming the field) when out of range or given more finely than kept.
    An inspection with a seat layout of its own has no seat heights: the vehicle's are for its seats.
    """
    _check_precision(cg_lift, cg_height_m)
    own_seats = seats is not None and [(s.role, s.x_m) for s in seats] != [
        (s.role, s.x_m) for s in vehicle_seats
    ]
    return {
        "cg_lift": None
        if cg_lift is None
        else {"lift_height_m": str(cg_lift.lift_height_m), "front_kg": [str(v) for v in cg_lift.front_kg]},
        "cg_height_m": None if cg_height_m is None else str(cg_height_m),
        "seat_heights_m": []
        if own_seats
        else [None if z is None else str(z) for z in figures.seat_heights_m],
    }


def checked_dynamics(record: WeighedRecord, figures: DynamicsFigures) -> Dynamics:
    """A new inspection's estimates, its CG-height weighing checked against the vehicle (422, named)."""
    try:
        return assess_dynamics(record_input(record, figures))
    except StabilityError as error:
        raise InvalidInput(error.message, field=error.field, rule=error.rule) from error


def _check_precision(cg_lift: CgLift | None, cg_height_m: Decimal | None) -> None:
    """Refuse a CG-height weighing out of range or given more finely than it is kept (as the API does)."""
    checks: list[tuple[Decimal, str, str, int, str]] = []
    if cg_lift is not None:
        checks.append((cg_lift.lift_height_m, "cg_lift.lift_height_m", "lift height", 4, "m"))
        many = len(cg_lift.front_kg) > 1
        checks += [
            (v, f"cg_lift.front_kg[{i}]" if many else "cg_lift.front_kg", "raised front reaction", 3, "kg")
            for i, v in enumerate(cg_lift.front_kg)
        ]
    if cg_height_m is not None:
        checks.append((cg_height_m, "cg_height_m", "centre of gravity height", 4, "m"))
    try:
        for value, name, what, places, unit in checks:
            low, high, _ = BOUNDS[name.split("[")[0]]
            check_number(
                value,
                field=name,
                minimum=Decimal(str(low)),
                maximum=Decimal(str(high)),
                decimals=places,
                what=what,
                unit=unit,
            )
    except StabilityError as error:
        raise InvalidInput(error.message, field=error.field, rule=error.rule) from error


def dynamics_input(
    *,
    wheelbase_m: Decimal,
    front_kg: Decimal,
    weighed_kg: Decimal,
    cases: Sequence[tuple[int, Decimal, Decimal, bool]],
    figures: DynamicsFigures,
    stored: dict[str, Any] | None,
    has_load_items: bool,
    layout: Layout = DELTA,
) -> DynamicsInput:
    """The pure core's input from an inspection's stored figures (the same at submission and later)."""
    stored = stored or {}
    vehicle = core_figures(figures)
    heights = tuple(None if z is None else float(z) for z in stored.get("seat_heights_m", []))
    lift = stored.get("cg_lift")
    given = stored.get("cg_height_m")
    return DynamicsInput(
        wheelbase_m=float(wheelbase_m),
        front_level_kg=float(front_kg),
        cases=tuple(CaseLoad(k, float(total), float(rear), ok) for k, total, rear, ok in cases),
        vehicle=replace(vehicle, seat_heights_m=heights),
        cg_lift=None
        if lift is None
        else AxleLift(float(lift["lift_height_m"]), float(_mean(lift["front_kg"]))),
        cg_height_m=None if given is None else float(given),
        has_load_items=has_load_items,
        weighed_total_kg=float(weighed_kg),
        n_front=layout.n_front,
        n_rear=layout.n_rear,
    )


def _axle(weighing: Weighing, wheels: Sequence[str]) -> Decimal:
    """An axle's load: its wheels' stored means added up (the delta's front axle: its one wheel)."""
    return sum((getattr(weighing, wheel) for wheel in wheels), Decimal(0))


def _mean(values: Sequence[str]) -> Fraction:
    return sum((Fraction(Decimal(v)) for v in values), Fraction(0)) / len(values)


def record_input(record: WeighedRecord, figures: DynamicsFigures) -> DynamicsInput:
    """The core's input for an inspection's stored values and the vehicle's figures it names."""
    return _weighing_input(record, record.cases, figures)


def _weighing_input(
    weighing: Weighing, cases: Sequence[WeighedCase], figures: DynamicsFigures
) -> DynamicsInput:
    layout = layout_named(weighing.layout)
    front = _axle(weighing, layout.front_wheels)
    weighed = (
        weighing.overall_kg
        if weighing.overall_kg is not None
        else front + _axle(weighing, layout.rear_wheels)
    )
    return dynamics_input(
        wheelbase_m=weighing.wheelbase_m,
        front_kg=front,
        weighed_kg=weighed,
        cases=[(c.occupants, c.total_kg, c.rear_kg, c.compliant) for c in cases],
        figures=figures,
        stored=weighing.dynamics_input,
        has_load_items=bool(weighing.occupant_config.get("load_items")),
        layout=layout,
    )


def stored_input(inspection: EstimatedInspection) -> DynamicsInput:
    """The core's input for a stored inspection."""
    return _weighing_input(
        inspection, inspection.loading_cases, revision_figures(inspection.dynamics_revision)
    )


def inspection_dynamics(inspection: EstimatedInspection) -> tuple[DynamicsInput, Dynamics]:
    """A stored inspection's estimates (inputs checked when it was stored)."""
    data = stored_input(inspection)
    return data, assess_dynamics(data)


def lift_inputs(data: DynamicsInput) -> dict[str, float | None]:
    """The CG-height inputs as shown beside the figures."""
    lift = data.cg_lift
    return {
        "cg_lift_height_m": None if lift is None else lift.lift_height_m,
        "cg_lift_front_kg": None if lift is None else round(lift.front_kg, 3),
        "cg_height_given_m": data.cg_height_m,
    }
