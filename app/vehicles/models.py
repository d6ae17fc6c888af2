"""Vehicle and seat tables."""

from __future__ import annotations

from datetime import datetime
from decimal import Decimal
from typing import TYPE_CHECKING

from sqlalchemy import CheckConstraint, ForeignKey, Integer, Numeric, String
from sqlalchemy.orm import Mapped, mapped_column, relationship

from app.db import Base, UTCDateTime, utcnow

if TYPE_CHECKING:
    from app.dynamics.models import VehicleDynamicsRevision


class Vehicle(Base):
    """A registered tricycle: identity, wheelbase and seat layout."""

    __tablename__ = "vehicle"
    __table_args__ = (CheckConstraint("layout IN ('delta', 'tadpole', 'quadricycle')", name="layout"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    registration_number: Mapped[str] = mapped_column(String(32))
    registration_key: Mapped[str] = mapped_column(String(32), unique=True)
    make: Mapped[str] = mapped_column(String(80))
    model: Mapped[str] = mapped_column(String(80))
    model_year: Mapped[int | None] = mapped_column(Integer)
    chassis_number: Mapped[str | None] = mapped_column(String(64))
    wheelbase_m: Mapped[Decimal] = mapped_column(Numeric(6, 4))
    # The axle layout (app/stability/layout.py), fixed at registration: a database trigger refuses to
    # change it, so every inspection of the vehicle was weighed on the same wheels.
    layout: Mapped[str] = mapped_column(String(16), server_default="delta", default="delta")
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)

    seats: Mapped[list[Seat]] = relationship(
        back_populates="vehicle", order_by="Seat.position", cascade="all, delete-orphan", lazy="selectin"
    )
    # Every version of the figures for the estimates, oldest first (app/dynamics/models.py).
    dynamics_revisions: Mapped[list[VehicleDynamicsRevision]] = relationship(
        back_populates="vehicle", order_by="VehicleDynamicsRevision.revision"
    )


class Seat(Base):
    """One seat of a vehicle's layout, driver at position 0."""

    __tablename__ = "seat"
    __table_args__ = (CheckConstraint("role IN ('driver', 'passenger')", name="role"),)

    vehicle_id: Mapped[int] = mapped_column(ForeignKey("vehicle.id", ondelete="CASCADE"), primary_key=True)
    position: Mapped[int] = mapped_column(Integer, primary_key=True)
    role: Mapped[str] = mapped_column(String(16))
    x_m: Mapped[Decimal] = mapped_column(Numeric(6, 4))

    vehicle: Mapped[Vehicle] = relationship(back_populates="seats")
