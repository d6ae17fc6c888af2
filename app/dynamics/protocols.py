"""What the estimates read of a vehicle and of an inspection, whose models live in the packages above.

Vehicles and inspections use the figures and the estimates, so this package imports neither: it names
the attributes it reads, and their models have them (docs/architecture.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from decimal import Decimal
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    from app.dynamics.models import VehicleDynamicsRevision


class FiguredVehicle(Protocol):
    """A registered vehicle as its figures read it: its seats, its key and every revision of the figures."""

    @property
    def id(self) -> int | None:
        """None until the vehicle is stored."""

    @property
    def registration_key(self) -> str:
        """The normalised registration, in the vehicle's address."""

    @property
    def layout(self) -> str:
        """The axle layout's name (delta, tadpole, quadricycle)."""

    @property
    def seats(self) -> Sequence[object]:
        """The seat layout, driver first (the figures give one height per seat)."""

    @property
    def dynamics_revisions(self) -> Sequence[VehicleDynamicsRevision]:
        """Every revision of the figures, oldest first."""


class WeighedCase(Protocol):
    """One loading case as stored: its load and its verdict."""

    @property
    def occupants(self) -> int:
        """0 for the driver alone, then one more occupant per case."""

    @property
    def total_kg(self) -> Decimal:
        """The case's total mass."""

    @property
    def rear_kg(self) -> Decimal:
        """The case's mass on the rear wheels."""

    @property
    def compliant(self) -> bool:
        """The case's verdict, as decided."""


class StoredCase(WeighedCase, Protocol):
    """A loading case as an inspection's row keeps it, with its LSF."""

    @property
    def lsf(self) -> Decimal:
        """The load share factor, rounded as stored."""


class Weighing(Protocol):
    """The stored values of one inspection the estimates start from."""

    @property
    def wheelbase_m(self) -> Decimal:
        """The wheelbase used."""

    @property
    def layout(self) -> str:
        """The axle layout weighed (delta, tadpole, quadricycle): which of the wheels below it has."""

    @property
    def front_kg(self) -> Decimal | None:
        """A delta's front wheel's reading, level."""

    @property
    def left_front_kg(self) -> Decimal | None:
        """The left front wheel's reading (a tadpole's or a quadricycle's)."""

    @property
    def right_front_kg(self) -> Decimal | None:
        """The right front wheel's reading (a tadpole's or a quadricycle's)."""

    @property
    def left_rear_kg(self) -> Decimal | None:
        """The left rear wheel's reading (a delta's or a quadricycle's)."""

    @property
    def right_rear_kg(self) -> Decimal | None:
        """The right rear wheel's reading (a delta's or a quadricycle's)."""

    @property
    def rear_kg(self) -> Decimal | None:
        """A tadpole's rear wheel's reading."""

    @property
    def overall_kg(self) -> Decimal | None:
        """The overall weight, where it was weighed."""

    @property
    def occupant_config(self) -> dict[str, Any]:
        """The seats and the load items used."""

    @property
    def dynamics_input(self) -> dict[str, Any] | None:
        """The CG-height weighing and the seat heights kept for the estimates."""


class WeighedRecord(Weighing, Protocol):
    """An inspection's record before or after it is stored, with its loading cases."""

    @property
    def cases(self) -> Sequence[WeighedCase]:
        """Table 4, lightest case first."""


class EstimatedInspection(Weighing, Protocol):
    """A stored inspection, with its rows and the revision of the vehicle's figures it was assessed with."""

    @property
    def id(self) -> int:
        """The inspection's number."""

    @property
    def loading_cases(self) -> Sequence[StoredCase]:
        """Table 4 as stored, lightest case first."""

    @property
    def dynamics_revision(self) -> VehicleDynamicsRevision | None:
        """The vehicle's figures in force when it was weighed (None: none on file)."""
