"""Inspection, reading and loading-case tables: the result as computed at the time, kept for good."""

from __future__ import annotations

from datetime import date, datetime
from decimal import Decimal
from typing import Any

from sqlalchemy import JSON, Boolean, CheckConstraint, Date, ForeignKey, Index, Integer, Numeric, String
from sqlalchemy.orm import Mapped, mapped_column, relationship

from app.db import Base, UTCDateTime, utcnow
from app.dynamics.models import VehicleDynamicsRevision
from app.stations.models import Station
from app.vehicles.models import Vehicle


class Inspection(Base):
    """One weighing session of one vehicle, with the settings in force and the verdict as decided."""

    __tablename__ = "inspection"
    __table_args__ = (
        # A vehicle's history, in the page's order; on PostgreSQL read from the index alone.
        Index(
            "ix_inspection_vehicle_history",
            "vehicle_id",
            "created_at",
            "id",
            postgresql_include=["compliant", "max_compliant_occupants", "station_id"],
        ),
        Index("ix_inspection_compliant_created_at", "compliant", "created_at"),
        Index("ix_inspection_station_id_created_at", "station_id", "created_at"),
        # The day's and the period's counts: on PostgreSQL an index-only scan.
        Index("ix_inspection_created_at", "created_at", postgresql_include=["compliant", "station_id"]),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    vehicle_id: Mapped[int] = mapped_column(ForeignKey("vehicle.id"))
    # The plate as it was when weighed: what a certificate of this weighing certifies (the database
    # refuses one that differs from the vehicle's, and a vehicle's plate is never rewritten).
    registration_number: Mapped[str] = mapped_column(String(32))
    station_id: Mapped[int | None] = mapped_column(ForeignKey("station.id"))
    user_id: Mapped[int | None] = mapped_column(ForeignKey("user_account.id"))
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)

    wheelbase_m: Mapped[Decimal] = mapped_column(Numeric(6, 4))
    occupant_mass_kg: Mapped[Decimal] = mapped_column(Numeric(7, 3))
    sum_tolerance: Mapped[Decimal] = mapped_column(Numeric(6, 4))
    rules_version: Mapped[str] = mapped_column(String(32))
    # Snapshot of the seats and load items used: [{"role", "x_m"}], [{"label", "mass_kg", "x_m"}].
    occupant_config: Mapped[dict[str, Any]] = mapped_column(JSON)

    # The axle layout assessed under: always the vehicle's (a database trigger checks it).
    layout: Mapped[str] = mapped_column(String(16), server_default="delta", default="delta")
    # Each wheel's mean reading; null for a wheel the layout does not have.
    front_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    left_rear_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    right_rear_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    left_front_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    right_front_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    rear_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    overall_kg: Mapped[Decimal | None] = mapped_column(Numeric(10, 4))
    cg_from_front_m: Mapped[Decimal] = mapped_column(Numeric(8, 5))
    compliant: Mapped[bool] = mapped_column(Boolean)
    max_compliant_occupants: Mapped[int] = mapped_column(Integer)
    # The station scale's calibration in force when the readings were taken (None: not on record).
    calibration_certificate: Mapped[str | None] = mapped_column(String(64))
    calibration_valid_until: Mapped[date | None] = mapped_column(Date)
    # Beyond the static test (estimates): the vehicle's figures in force, and the CG-height weighing
    # {"cg_lift": {"lift_height_m", "front_kg": [...]}, "cg_height_m", "seat_heights_m": [...]}.
    # No foreign key: SQLite could not drop the column again without rebuilding this table.
    dynamics_revision_id: Mapped[int | None] = mapped_column(Integer)
    dynamics_input: Mapped[dict[str, Any] | None] = mapped_column(JSON)

    vehicle: Mapped[Vehicle] = relationship(lazy="joined")
    station: Mapped[Station | None] = relationship(lazy="joined")
    dynamics_revision: Mapped[VehicleDynamicsRevision | None] = relationship(
        primaryjoin="foreign(Inspection.dynamics_revision_id) == VehicleDynamicsRevision.id", lazy="joined"
    )
    readings: Mapped[list[Reading]] = relationship(
        order_by="(Reading.case_occupants, Reading.wheel, Reading.sequence)", lazy="selectin"
    )
    loading_cases: Mapped[list[LoadingCaseRow]] = relationship(
        order_by="LoadingCaseRow.occupants", lazy="selectin"
    )


class Reading(Base):
    """One raw scale value: a wheel (or the overall weight) of the base weighing or a measured case."""

    __tablename__ = "reading"
    __table_args__ = (
        CheckConstraint(
            "wheel IN ('front_kg', 'left_rear_kg', 'right_rear_kg', 'overall_kg', "
            "'left_front_kg', 'right_front_kg', 'rear_kg')",
            name="wheel",
        ),
    )

    inspection_id: Mapped[int] = mapped_column(ForeignKey("inspection.id"), primary_key=True)
    case_occupants: Mapped[int] = mapped_column(Integer, primary_key=True)  # 0: the base weighing
    wheel: Mapped[str] = mapped_column(String(16), primary_key=True)
    sequence: Mapped[int] = mapped_column(Integer, primary_key=True)
    value_kg: Mapped[Decimal] = mapped_column(Numeric(10, 3))


class LoadingCaseRow(Base):
    """One row of Table 4 as computed at inspection time (exact values rounded to 6 places)."""

    __tablename__ = "loading_case"

    inspection_id: Mapped[int] = mapped_column(ForeignKey("inspection.id"), primary_key=True)
    occupants: Mapped[int] = mapped_column(Integer, primary_key=True)
    total_kg: Mapped[Decimal] = mapped_column(Numeric(12, 6))
    rear_kg: Mapped[Decimal] = mapped_column(Numeric(12, 6))
    lsf: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    variance: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    compliant: Mapped[bool] = mapped_column(Boolean)
    measured: Mapped[bool] = mapped_column(Boolean, default=False)
    # The exact LSF as a fraction "p/q", so the stored verdict can be re-checked exactly.
    lsf_exact: Mapped[str] = mapped_column(String(200))
