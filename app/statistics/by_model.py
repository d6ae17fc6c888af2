"""Statistics per make and model: the vehicles inspected in a period, the share compliant, and the newest
type assessment of each model."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import tzinfo
from typing import Any

from sqlalchemy import Subquery, func, select
from sqlalchemy.orm import InstrumentedAttribute, Session, lazyload

from app.inspections.models import Inspection
from app.stability import LAYOUT_NAMES
from app.statistics.service import Period
from app.type_assessments.models import TypeAssessmentRecord
from app.vehicles.models import Vehicle

MAX_MODELS = 100  # the page lists the most inspected models first


@dataclass(frozen=True)
class ModelCounts:
    """One make and model: vehicles inspected in the period, how many complied at their latest weighing."""

    make: str
    model: str
    vehicles: int
    compliant: int
    type_assessment_id: int | None  # the newest type assessment of the model, any time
    type_compliant: bool | None
    type_max_compliant_occupants: int | None

    @property
    def compliant_percent(self) -> float:
        """The share of the vehicles whose latest inspection in the period complied, in per cent."""
        return 100 * self.compliant / self.vehicles


def _key(text: str) -> str:
    return text.strip().lower()


def _latest_per_vehicle(
    column: InstrumentedAttribute[Any], *, period: Period, zone: tzinfo, station_id: int | None
) -> Subquery:
    """Each inspection of the period (at one station, if given) with `column`, its verdict and its rank
    among its vehicle's inspections there, newest first: rank 1 is the vehicle's latest."""
    start, end = period.utc_bounds(zone)
    latest = select(
        column,
        Inspection.compliant,
        func.row_number()
        .over(
            partition_by=Inspection.vehicle_id, order_by=(Inspection.created_at.desc(), Inspection.id.desc())
        )
        .label("rank"),
    ).where(Inspection.created_at >= start, Inspection.created_at < end)
    if station_id is not None:
        latest = latest.where(Inspection.station_id == station_id)
    return latest.subquery()


def model_counts(
    session: Session, *, period: Period, zone: tzinfo, station_id: int | None = None
) -> list[ModelCounts]:
    """Per make and model (case and spaces ignored), the vehicles inspected in the period and the share
    whose latest inspection there complied, most vehicles first, with the model's newest type assessment."""
    ranked = _latest_per_vehicle(Inspection.vehicle_id, period=period, zone=zone, station_id=station_id)
    rows = session.execute(
        select(Vehicle.make, Vehicle.model, ranked.c.compliant)
        .join(ranked, ranked.c.vehicle_id == Vehicle.id)
        .where(ranked.c.rank == 1)
    ).all()
    grouped: dict[tuple[str, str], tuple[str, str, int, int]] = {}
    for make, model, compliant in rows:
        key = (_key(make), _key(model))
        shown_make, shown_model, vehicles, passed = grouped.get(key, (make.strip(), model.strip(), 0, 0))
        grouped[key] = (shown_make, shown_model, vehicles + 1, passed + int(bool(compliant)))
    newest = newest_type_assessments(session)
    found = []
    for key, (make, model, vehicles, passed) in grouped.items():
        record = newest.get(key)
        found.append(
            ModelCounts(
                make,
                model,
                vehicles,
                passed,
                record.id if record else None,
                record.compliant if record else None,
                record.max_compliant_occupants if record else None,
            )
        )
    found.sort(key=lambda m: (-m.vehicles, m.make.lower(), m.model.lower()))
    return found[:MAX_MODELS]


@dataclass(frozen=True)
class LayoutCounts:
    """One axle layout: vehicles inspected in the period, how many complied at their latest weighing."""

    layout: str
    vehicles: int
    compliant: int

    @property
    def compliant_percent(self) -> float:
        """The share of the vehicles whose latest inspection in the period complied, in per cent."""
        return 100 * self.compliant / self.vehicles


def layout_counts(
    session: Session, *, period: Period, zone: tzinfo, station_id: int | None = None
) -> list[LayoutCounts]:
    """Per axle layout (delta, tadpole, quadricycle, in that order), the vehicles inspected in the period
    and how many complied at their latest inspection there (each under its own layout's limit)."""
    ranked = _latest_per_vehicle(Inspection.layout, period=period, zone=zone, station_id=station_id)
    rows = session.execute(
        select(ranked.c.layout, func.count(), func.count().filter(ranked.c.compliant))
        .where(ranked.c.rank == 1)
        .group_by(ranked.c.layout)
    ).all()
    found = {layout: LayoutCounts(layout, vehicles, compliant or 0) for layout, vehicles, compliant in rows}
    return [found[name] for name in LAYOUT_NAMES if name in found]


def newest_type_assessments(session: Session) -> dict[tuple[str, str], TypeAssessmentRecord]:
    """The newest type assessment of each make and model (case and spaces ignored)."""
    ranked = select(
        TypeAssessmentRecord.id,
        func.row_number()
        .over(
            partition_by=(
                func.lower(func.trim(TypeAssessmentRecord.make)),
                func.lower(func.trim(TypeAssessmentRecord.model)),
            ),
            order_by=(TypeAssessmentRecord.created_at.desc(), TypeAssessmentRecord.id.desc()),
        )
        .label("rank"),
    ).subquery()
    records = session.scalars(
        select(TypeAssessmentRecord)
        .join(ranked, ranked.c.id == TypeAssessmentRecord.id)
        .where(ranked.c.rank == 1)
        .options(lazyload(TypeAssessmentRecord.members), lazyload(TypeAssessmentRecord.cases))
    ).all()
    return {(_key(r.make), _key(r.model)): r for r in records}
