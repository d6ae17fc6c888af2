"""Record a vehicle's figures beyond the weighing: every change is a new revision, none is overwritten."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from decimal import Decimal

from sqlalchemy import func, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from app.dynamics.models import DYNAMICS_FIELDS, VehicleDynamicsRevision
from app.dynamics.protocols import FiguredVehicle
from app.errors import Conflict, InvalidInput
from app.stability import StabilityError
from app.stability.dynamics import VehicleDynamics, check_vehicle
from app.stability.layout import layout_named

# Decimal places each figure is stored to (metres to 0.1 mm, stiffness to 0.1 N/rad).
PLACES = {
    "track_m": 4,
    "front_track_m": 4,
    "wheel_radius_m": 4,
    "front_cornering_stiffness_n_per_rad": 1,
    "rear_cornering_stiffness_n_per_rad": 1,
    "drag_area_m2": 4,
    "centre_of_pressure_height_m": 4,
    "seat_heights_m": 4,
}


@dataclass(frozen=True)
class DynamicsFigures:
    """What a door hands the service; None where a figure is not known."""

    track_m: Decimal | None = None
    wheel_radius_m: Decimal | None = None
    seat_heights_m: tuple[Decimal | None, ...] = ()
    front_cornering_stiffness_n_per_rad: Decimal | None = None
    rear_cornering_stiffness_n_per_rad: Decimal | None = None
    drag_area_m2: Decimal | None = None
    centre_of_pressure_height_m: Decimal | None = None
    front_track_m: Decimal | None = None


def _float(value: Decimal | None) -> float | None:
    return None if value is None else float(value)


def core_figures(figures: DynamicsFigures) -> VehicleDynamics:
    """The pure core's view of the figures, in floats."""
    return VehicleDynamics(
        seat_heights_m=tuple(_float(z) for z in figures.seat_heights_m),
        **{name: _float(getattr(figures, name)) for name in DYNAMICS_FIELDS},
    )


def check_figures(figures: DynamicsFigures, *, seat_count: int, front_wheels: int = 1) -> None:
    """Refuse an implausible figure (422 naming the field), more seat heights than seats, or a front
    track for a vehicle with one front wheel."""
    if front_wheels == 1 and figures.front_track_m is not None:
        raise InvalidInput(
            "front_track_m: a vehicle with one front wheel has no front track; leave it out",
            field="front_track_m",
            rule="front_track",
        )
    if len(figures.seat_heights_m) > seat_count:
        raise InvalidInput(
            f"seats: {len(figures.seat_heights_m)} seat heights were given for {seat_count} seats",
            field="seats",
            rule="seat_heights",
        )
    try:
        check_vehicle(core_figures(figures))
    except StabilityError as error:
        raise InvalidInput(error.message, field=error.field, rule=error.rule) from error
    named = [(name, getattr(figures, name), PLACES[name]) for name in DYNAMICS_FIELDS]
    named += [(f"seats[{i}].z_m", z, PLACES["seat_heights_m"]) for i, z in enumerate(figures.seat_heights_m)]
    for name, value, places in named:
        exponent = value.as_tuple().exponent if value is not None else 0
        if isinstance(exponent, int) and -exponent > places:
            raise InvalidInput(
                f"{name}: give it to at most {places} decimal places", field=name, rule="precision"
            )


def new_revision(
    session: Session, vehicle: FiguredVehicle, figures: DynamicsFigures
) -> VehicleDynamicsRevision:
    """Add the next revision of the vehicle's figures to the session (the caller commits)."""
    check_figures(figures, seat_count=len(vehicle.seats), front_wheels=layout_named(vehicle.layout).n_front)
    latest = 0
    if vehicle.id is not None:
        latest = (
            session.scalar(
                select(func.max(VehicleDynamicsRevision.revision)).where(
                    VehicleDynamicsRevision.vehicle_id == vehicle.id
                )
            )
            or 0
        )
    revision = VehicleDynamicsRevision(
        vehicle=vehicle,
        revision=latest + 1,
        seat_heights_m=[None if z is None else str(z) for z in figures.seat_heights_m],
        **{name: getattr(figures, name) for name in DYNAMICS_FIELDS},
    )
    session.add(revision)
    return revision


def record_figures(
    session: Session, vehicle: FiguredVehicle, figures: DynamicsFigures
) -> VehicleDynamicsRevision:
    """Store a new revision of the vehicle's figures and commit; the older ones stay as they were."""
    revision = new_revision(session, vehicle, figures)
    try:
        session.commit()
    except IntegrityError as error:  # a simultaneous change took the same revision number
        session.rollback()
        raise Conflict(
            "track_m: someone else changed the figures at the same moment; look at them and send again",
            field="track_m",
            rule="concurrent_change",
        ) from error
    return revision


def current_revision(session: Session, vehicle_id: int) -> VehicleDynamicsRevision | None:
    """The vehicle's latest revision, or None for a vehicle registered before figures were kept."""
    return session.scalars(
        select(VehicleDynamicsRevision)
        .where(VehicleDynamicsRevision.vehicle_id == vehicle_id)
        .order_by(VehicleDynamicsRevision.revision.desc())
        .limit(1)
    ).first()


def revision_figures(revision: VehicleDynamicsRevision | None) -> DynamicsFigures:
    """A stored revision's figures (all unknown for none)."""
    if revision is None:
        return DynamicsFigures()
    return DynamicsFigures(
        seat_heights_m=tuple(None if z is None else Decimal(z) for z in revision.seat_heights_m),
        **{name: getattr(revision, name) for name in DYNAMICS_FIELDS},
    )


def seat_heights(values: Sequence[Decimal | None]) -> tuple[Decimal | None, ...]:
    """Seat heights without the unknown ones at the end (a layout may give heights for its first seats)."""
    heights = list(values)
    while heights and heights[-1] is None:
        heights.pop()
    return tuple(heights)
