"""Type assessment tables: the inspections used, the settings and the results as computed, kept for good."""

from __future__ import annotations

from datetime import datetime
from decimal import Decimal
from typing import Any

from sqlalchemy import JSON, Boolean, ForeignKey, Index, Integer, Numeric, String
from sqlalchemy.orm import Mapped, mapped_column, relationship

from app.db import Base, UTCDateTime, utcnow
from app.inspections.models import Inspection


class TypeAssessmentRecord(Base):
    """One assessment of a make and model from two or more vehicles' inspections; never recomputed."""

    __tablename__ = "type_assessment"
    __table_args__ = (Index("ix_type_assessment_make_model_created_at", "make", "model", "created_at"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    created_at: Mapped[datetime] = mapped_column(UTCDateTime(), default=utcnow)
    station_id: Mapped[int | None] = mapped_column(ForeignKey("station.id"))  # asked over the API
    user_id: Mapped[int | None] = mapped_column(ForeignKey("user_account.id"))  # asked from the page
    make: Mapped[str] = mapped_column(String(80))
    model: Mapped[str] = mapped_column(String(80))
    model_year: Mapped[int | None] = mapped_column(Integer)  # None: every model year

    rules_version: Mapped[str] = mapped_column(String(64))
    occupant_mass_kg: Mapped[Decimal] = mapped_column(Numeric(7, 3))
    wheelbase_m: Mapped[Decimal] = mapped_column(Numeric(6, 4))
    # Snapshot of the common seats and load items: [{"role", "x_m"}], [{"label", "mass_kg", "x_m"}].
    occupant_config: Mapped[dict[str, Any]] = mapped_column(JSON)
    confidence: Mapped[Decimal] = mapped_column(Numeric(4, 3))  # one-sided, 0.95
    t_value: Mapped[Decimal] = mapped_column(Numeric(12, 9))  # Student's t(confidence, n - 1) used
    vehicle_count: Mapped[int] = mapped_column(Integer)
    compliant: Mapped[bool] = mapped_column(Boolean)  # by the confident verdict
    max_compliant_occupants: Mapped[int] = mapped_column(Integer)

    members: Mapped[list[TypeAssessmentInspection]] = relationship(
        order_by="TypeAssessmentInspection.position", lazy="selectin"
    )
    cases: Mapped[list[TypeAssessmentCase]] = relationship(
        order_by="TypeAssessmentCase.occupants", lazy="selectin"
    )


class TypeAssessmentInspection(Base):
    """One inspection a type assessment used, in the order given."""

    __tablename__ = "type_assessment_inspection"

    type_assessment_id: Mapped[int] = mapped_column(ForeignKey("type_assessment.id"), primary_key=True)
    position: Mapped[int] = mapped_column(Integer, primary_key=True)
    inspection_id: Mapped[int] = mapped_column(ForeignKey("inspection.id"), index=True)

    inspection: Mapped[Inspection] = relationship(lazy="joined")


class TypeAssessmentCase(Base):
    """One loading case of a type: its Table 4 row from the mean readings and the vehicles' spread."""

    __tablename__ = "type_assessment_case"

    type_assessment_id: Mapped[int] = mapped_column(ForeignKey("type_assessment.id"), primary_key=True)
    occupants: Mapped[int] = mapped_column(Integer, primary_key=True)
    total_kg: Mapped[Decimal] = mapped_column(Numeric(12, 6))
    rear_kg: Mapped[Decimal] = mapped_column(Numeric(12, 6))
    lsf: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    variance: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    compliant: Mapped[bool] = mapped_column(Boolean)  # the ratio of the means, as the study decides
    lsf_exact: Mapped[str] = mapped_column(String(400))
    min_lsf: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    mean_lsf: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    max_lsf: Mapped[Decimal] = mapped_column(Numeric(9, 8))
    sd_lsf: Mapped[Decimal] = mapped_column(Numeric(12, 8))
    upper_95_lsf: Mapped[Decimal] = mapped_column(Numeric(12, 8))
    confident_compliant: Mapped[bool] = mapped_column(Boolean)
