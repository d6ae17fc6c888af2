"""A vehicle's figures beyond the weighing, one append-only revision per change."""

from __future__ import annotations

from datetime import datetime
from decimal import Decimal
from typing import Any

from sqlalchemy import JSON, ForeignKey, Integer, Numeric, UniqueConstraint
from sqlalchemy.orm import Mapped, mapped_column, relationship

from app.db import Base, UTCDateTime, utcnow
from app.dynamics.protocols import FiguredVehicle

# The figures of a revision, in the order the pages and the API show them.
DYNAMICS_FIELDS = (
    "track_m",
    "wheel_radius_m",
    "front_cornering_stiffness_n_per_rad",
    "rear_cornering_stiffness_n_per_rad",
    "drag_area_m2",
    "centre_of_pressure_height_m",
    "front_track_m",
)


class VehicleDynamicsRevision(Base):
    """Rear track, wheel radius, seat heights, tyre stiffness and drag as given at one time; never changed.

    Past inspections name the revision they were assessed with, so a later correction never
    rewrites their estimates.
    """

    __tablename__ = "vehicle_dynamics_revision"
    __table_args__ = (UniqueConstraint("vehicle_id", "revision"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    vehicle_id: Mapped[int] = mapped_column(ForeignKey("vehicle.id"))
    revision: Mapped[int] = mapped_column(Integer)  # 1, 2, ... per vehicle
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    track_m: Mapped[Decimal | None] = mapped_column(Numeric(6, 4))
    wheel_radius_m: Mapped[Decimal | None] = mapped_column(Numeric(6, 4))
    # The seated CG height of each seat, driver first, as strings ("0.75") or null where unknown.
    seat_heights_m: Mapped[list[Any]] = mapped_column(JSON)
    front_cornering_stiffness_n_per_rad: Mapped[Decimal | None] = mapped_column(Numeric(9, 1))
    rear_cornering_stiffness_n_per_rad: Mapped[Decimal | None] = mapped_column(Numeric(9, 1))
    drag_area_m2: Mapped[Decimal | None] = mapped_column(Numeric(6, 4))
    centre_of_pressure_height_m: Mapped[Decimal | None] = mapped_column(Numeric(6, 4))
    # Two front wheels (tadpole, quadricycle) tip about their track; null on a delta.
    front_track_m: Mapped[Decimal | None] = mapped_column(Numeric(6, 4))

    # By name: the vehicle's model is in app/vehicles/, above this package.
    vehicle: Mapped[FiguredVehicle] = relationship(
        "Vehicle", back_populates="dynamics_revisions", lazy="joined"
    )
