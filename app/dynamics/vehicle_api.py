"""The vehicle API's figures for the estimates: body to service, stored revision to answer."""

from __future__ import annotations

from app.dynamics.models import DYNAMICS_FIELDS, VehicleDynamicsRevision
from app.dynamics.protocols import FiguredVehicle
from app.dynamics.schemas import VehicleDynamicsIn, VehicleDynamicsOut
from app.dynamics.service import DynamicsFigures, seat_heights


def dynamics_figures(body: VehicleDynamicsIn) -> DynamicsFigures:
    """The service's figures from a registration body (seat heights from its seats' `z_m`)."""
    seats = getattr(body, "seats", [])
    return DynamicsFigures(
        seat_heights_m=seat_heights([getattr(seat, "z_m", None) for seat in seats]),
        **{name: getattr(body, name) for name in DYNAMICS_FIELDS},
    )


def revision_out(revision: VehicleDynamicsRevision) -> VehicleDynamicsOut:
    """The API view of one stored revision."""
    figures = {name: getattr(revision, name) for name in DYNAMICS_FIELDS}
    return VehicleDynamicsOut(
        revision=revision.revision,
        seat_heights_m=[None if z is None else float(z) for z in revision.seat_heights_m],
        **{name: None if value is None else float(value) for name, value in figures.items()},
    )


def dynamics_out(vehicle: FiguredVehicle) -> VehicleDynamicsOut | None:
    """The vehicle's figures in force, or None for a vehicle registered before they were kept."""
    revisions = vehicle.dynamics_revisions
    return revision_out(revisions[-1]) if revisions else None
