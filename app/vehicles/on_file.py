"""What an inspection needs of the vehicle weighed, as a plain value (not an ORM row)."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from app.dynamics.models import VehicleDynamicsRevision
from app.dynamics.service import DynamicsFigures, revision_figures
from app.stability import DELTA, Layout, Seat, layout_named
from app.vehicles.models import Vehicle


@dataclass(frozen=True)
class VehicleOnFile:
    """A registered vehicle: its registration as printed, wheelbase, seats, and its figures in force."""

    id: int
    registration_number: str
    wheelbase_m: Decimal
    seats: tuple[Seat, ...]
    figures: DynamicsFigures  # for the estimates; all unknown when none are on file
    figures_revision_id: int | None  # the revision the figures come from (None: none on file)
    layout: Layout = DELTA  # the axle layout, fixed at registration

    @classmethod
    def of(cls, vehicle: Vehicle, revision: VehicleDynamicsRevision | None) -> VehicleOnFile:
        """The value of a vehicle row, its seats and its latest revision of figures."""
        return cls(
            id=vehicle.id,
            registration_number=vehicle.registration_number,
            wheelbase_m=vehicle.wheelbase_m,
            seats=tuple(Seat(s.role, s.x_m) for s in vehicle.seats),  # type: ignore[arg-type]
            figures=revision_figures(revision),
            figures_revision_id=revision.id if revision else None,
            layout=layout_named(vehicle.layout),
        )
