"""An inspection's estimates beyond the static test: checked and stored with it, computed from the record.

Estimates are floats from assumed inputs; they never change the verdict the static core decided.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from decimal import ROUND_HALF_EVEN, Decimal
from fractions import Fraction
from typing import Any

from sqlalchemy.orm import Session

from app.errors import InvalidInput
from app.stability import Assessment, Seat, StabilityError
from app.stability.dynamics import (
    BOUNDS,
    AxleLift,
    CaseLoad,
    Dynamics,
    DynamicsInput,
    VehicleDynamics,
    assess_dynamics,
)
from app.stability.validation import check_number
from app.vehicles.dynamics_models import VehicleDynamicsRevision
from app.vehicles.dynamics_service import core_figures, current_revision, revision_figures
from app.vehicles.models import Vehicle


@dataclass(frozen=True)
class CgLift:
    """The axle-lift weighing as sent: the lift height and the raised front wheel's readings."""

    lift_height_m: Decimal
    front_kg: tuple[Decimal, ...]

    @property
    def mean_front_kg(self) -> Fraction:
        """The raised front readings averaged, exactly."""
        return sum((Fraction(v) for v in self.front_kg), Fraction(0)) / len(self.front_kg)


@dataclass(frozen=True)
class StoredFigures:
    """What an inspection keeps for its estimates: the columns to store and the revision in force."""

    columns: dict[str, Any]
    revision: VehicleDynamicsRevision | None


def _four(value: Fraction) -> Decimal:
    return (Decimal(value.numerator) / Decimal(value.denominator)).quantize(
        Decimal("0.0001"), ROUND_HALF_EVEN
    )


def figures_for_inspection(
    session: Session,
    *,
    vehicle: Vehicle,
    result: Assessment,
    cg_lift: CgLift | None,
    cg_height_m: Decimal | None,
    seats: Sequence[Seat] | None,
    has_load_items: bool,
) -> StoredFigures:
    """Check the CG-height weighing against the vehicle's figures in force (422 naming the field).

    An inspection with a seat layout of its own has no seat heights: the vehicle's are for its seats.
    """
    _check_precision(cg_lift, cg_height_m)
    revision = current_revision(session, vehicle.id)
    own_seats = seats is not None and [(s.role, s.x_m) for s in seats] != [
        (s.role, s.x_m) for s in vehicle.seats
    ]
    heights = [] if own_seats else list(revision.seat_heights_m if revision else [])
    stored = {
        "cg_lift": None
        if cg_lift is None
        else {"lift_height_m": str(cg_lift.lift_height_m), "front_kg": [str(v) for v in cg_lift.front_kg]},
        "cg_height_m": None if cg_height_m is None else str(cg_height_m),
        "seat_heights_m": heights,
    }
    readings = result.readings
    data = dynamics_input(
        wheelbase_m=result.wheelbase_m,
        front_kg=_four(readings.front_kg),
        weighed_kg=_four(readings.total_kg),
        cases=[(c.occupants, _four(c.total_kg), _four(c.rear_kg), c.compliant) for c in result.cases],
        revision=revision,
        stored=stored,
        has_load_items=has_load_items,
    )
    try:
        assess_dynamics(data)
    except StabilityError as error:
        raise InvalidInput(error.message, field=error.field, rule=error.rule) from error
    columns = {"dynamics_revision_id": revision.id if revision else None, "dynamics_input": stored}
    return StoredFigures(columns, revision)


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
    revision: VehicleDynamicsRevision | None,
    stored: dict[str, Any] | None,
    has_load_items: bool,
) -> DynamicsInput:
    """The pure core's input from an inspection's stored figures (the same at submission and later)."""
    stored = stored or {}
    figures = core_figures(revision_figures(revision))
    heights = tuple(None if z is None else float(z) for z in stored.get("seat_heights_m", []))
    lift = stored.get("cg_lift")
    given = stored.get("cg_height_m")
    return DynamicsInput(
        wheelbase_m=float(wheelbase_m),
        front_level_kg=float(front_kg),
        cases=tuple(CaseLoad(k, float(total), float(rear), ok) for k, total, rear, ok in cases),
        vehicle=VehicleDynamics(
            track_m=figures.track_m,
            wheel_radius_m=figures.wheel_radius_m,
            seat_heights_m=heights,
            front_cornering_stiffness_n_per_rad=figures.front_cornering_stiffness_n_per_rad,
            rear_cornering_stiffness_n_per_rad=figures.rear_cornering_stiffness_n_per_rad,
            drag_area_m2=figures.drag_area_m2,
            centre_of_pressure_height_m=figures.centre_of_pressure_height_m,
        ),
        cg_lift=None
        if lift is None
        else AxleLift(float(lift["lift_height_m"]), float(_mean(lift["front_kg"]))),
        cg_height_m=None if given is None else float(given),
        has_load_items=has_load_items,
        weighed_total_kg=float(weighed_kg),
    )


def _mean(values: Sequence[str]) -> Fraction:
    return sum((Fraction(Decimal(v)) for v in values), Fraction(0)) / len(values)


def stored_input(inspection: Any) -> DynamicsInput:
    """The core's input for a stored inspection (an `Inspection` row)."""
    front = inspection.front_kg
    weighed = (
        inspection.overall_kg
        if inspection.overall_kg is not None
        else front + inspection.left_rear_kg + inspection.right_rear_kg
    )
    return dynamics_input(
        wheelbase_m=inspection.wheelbase_m,
        front_kg=front,
        weighed_kg=weighed,
        cases=[(c.occupants, c.total_kg, c.rear_kg, c.compliant) for c in inspection.loading_cases],
        revision=inspection.dynamics_revision,
        stored=inspection.dynamics_input,
        has_load_items=bool(inspection.occupant_config.get("load_items")),
    )


def inspection_dynamics(inspection: Any) -> tuple[DynamicsInput, Dynamics]:
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
