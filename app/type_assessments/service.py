"""Assess a make and model from stored inspections, store the outcome for good and read it back."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from decimal import Decimal
from typing import Any

from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.db import begin_write, utcnow
from app.errors import InvalidInput, NotFound
from app.inspections.models import Inspection
from app.inspections.record import quantize
from app.inspections.service import refusal
from app.stability import (
    RULES_VERSION,
    AssessmentInput,
    Layout,
    LoadItem,
    MeasuredCase,
    Rules,
    Seat,
    StabilityError,
    rules_version,
)
from app.stability.layout import ALL_WHEELS, OVERALL, layout_named
from app.stability.model import WheelReadings
from app.stability.type_assessment import Member, TypeAssessment, assess_type
from app.type_assessments.models import TypeAssessmentCase, TypeAssessmentInspection, TypeAssessmentRecord
from app.vehicles.models import Vehicle

TYPE_RULES_VERSION = f"{RULES_VERSION};type:mean-readings,t95-upper:v1"


def type_rules_version(layout: Layout) -> str:
    """A type assessment's rules: its layout's limit, then the type's method (the delta's as it was)."""
    return f"{rules_version(layout)};type:mean-readings,t95-upper:v1"


CONFIDENCE = Decimal("0.95")
MAX_VEHICLES = 500  # beyond this, choose the inspections (a bound on one request's work)


@dataclass(frozen=True)
class TypeRequest:
    """What a door hands the service: the model, and optionally the very inspections to use."""

    make: str
    model: str
    model_year: int | None = None
    inspection_ids: tuple[int, ...] | None = None  # None: the latest inspection of every vehicle


def _same_text(column: Any, value: str) -> Any:
    """A make or model matches whatever its case and surrounding spaces."""
    return func.lower(func.trim(column)) == value.strip().lower()


def _model_filter(request: TypeRequest) -> list[Any]:
    where = [_same_text(Vehicle.make, request.make), _same_text(Vehicle.model, request.model)]
    if request.model_year is not None:
        where.append(Vehicle.model_year == request.model_year)
    return where


def latest_inspections(
    session: Session, request: TypeRequest, *, station_id: int | None = None
) -> list[Inspection]:
    """The latest inspection of every vehicle of the model (a station: of those it weighed itself)."""
    ranked = select(
        Inspection.id,
        func.row_number()
        .over(
            partition_by=Inspection.vehicle_id, order_by=(Inspection.created_at.desc(), Inspection.id.desc())
        )
        .label("rank"),
    ).join(Inspection.vehicle)
    ranked = ranked.where(*_model_filter(request))
    if station_id is not None:
        ranked = ranked.where(Inspection.station_id == station_id)
    latest = ranked.subquery()
    ids = select(latest.c.id).where(latest.c.rank == 1).limit(MAX_VEHICLES + 1)
    found = session.scalars(
        select(Inspection)
        .join(Inspection.vehicle)
        .where(Inspection.id.in_(ids))
        .order_by(Vehicle.registration_key)
    ).all()
    return list(found)


def chosen_inspections(
    session: Session, request: TypeRequest, ids: Sequence[int], *, station_id: int | None = None
) -> list[Inspection]:
    """The inspections named, each of a different vehicle of the model; refusals name the list entry."""
    found: list[Inspection] = []
    vehicles: dict[int, int] = {}
    for index, inspection_id in enumerate(ids):
        field = f"inspection_ids[{index}]"
        inspection = session.get(Inspection, inspection_id)
        if inspection is None or (station_id is not None and inspection.station_id != station_id):
            raise NotFound(f"{field}: inspection {inspection_id} does not exist", field=field, rule="exists")
        vehicle = inspection.vehicle
        if not _of_model(vehicle, request):
            raise InvalidInput(
                f"{field}: inspection {inspection_id} is of {vehicle.registration_number}, a "
                f"{_model_name(vehicle.make, vehicle.model, vehicle.model_year)}, not a "
                f"{_model_name(request.make, request.model, request.model_year)}",
                field=field,
                rule="same_model",
            )
        if vehicle.id in vehicles:
            raise InvalidInput(
                f"{field}: inspections {ids[vehicles[vehicle.id]]} and {inspection_id} are both of "
                f"{vehicle.registration_number}; a type assessment takes one inspection per vehicle",
                field=field,
                rule="one_per_vehicle",
            )
        vehicles[vehicle.id] = index
        found.append(inspection)
    return found


def _of_model(vehicle: Vehicle, request: TypeRequest) -> bool:
    same = vehicle.make.strip().lower() == request.make.strip().lower()
    same = same and vehicle.model.strip().lower() == request.model.strip().lower()
    return same and (request.model_year is None or vehicle.model_year == request.model_year)


def _model_name(make: str, model: str, model_year: int | None) -> str:
    return f"{make} {model}" + (f" ({model_year})" if model_year is not None else "")


def member(inspection: Inspection, rules: Rules) -> Member:
    """The core's view of a stored inspection: its raw readings, geometry and the settings it had."""
    values: dict[int, dict[str, list[Decimal]]] = {}
    for reading in inspection.readings:
        values.setdefault(reading.case_occupants, {}).setdefault(reading.wheel, []).append(reading.value_kg)

    def readings(case: int) -> WheelReadings:
        wheels = values.get(case, {})
        return WheelReadings(**{wheel: tuple(wheels.get(wheel, ())) for wheel in (*ALL_WHEELS, OVERALL)})

    config = inspection.occupant_config
    data = AssessmentInput(
        readings=readings(0),
        wheelbase_m=inspection.wheelbase_m,
        seats=tuple(Seat(s["role"], Decimal(s["x_m"])) for s in config["seats"]),
        load_items=tuple(
            LoadItem(Decimal(i["mass_kg"]), Decimal(i["x_m"]), i["label"]) for i in config["load_items"]
        ),
        measured_cases=tuple(MeasuredCase(case, readings(case)) for case in sorted(values) if case > 0),
        occupant_mass_kg=inspection.occupant_mass_kg,
        layout=layout_named(inspection.layout),
    )
    own_rules = replace(
        rules, sum_tolerance=inspection.sum_tolerance, occupant_mass_kg=inspection.occupant_mass_kg
    )
    return Member(inspection.vehicle.registration_number, data, own_rules)


def inspections_for(
    session: Session, request: TypeRequest, *, station_id: int | None = None
) -> list[Inspection]:
    """The inspections a type assessment of this request would use, or the refusal naming the field."""
    if request.inspection_ids is not None:
        found = chosen_inspections(session, request, request.inspection_ids, station_id=station_id)
    else:
        found = latest_inspections(session, request, station_id=station_id)
        if len(found) > MAX_VEHICLES:
            raise InvalidInput(
                f"inspection_ids: more than {MAX_VEHICLES} vehicles of this model; choose the inspections",
                field="inspection_ids",
                rule="too_many",
            )
    if len(found) < 2:
        field = "inspection_ids" if request.inspection_ids is not None else "model"
        raise InvalidInput(
            f"{field}: a type assessment needs inspections of at least two vehicles of the "
            f"{_model_name(request.make, request.model, request.model_year)}; found {len(found)}",
            field=field,
            rule="too_few",
        )
    return found


def create_type_assessment(
    session: Session,
    *,
    request: TypeRequest,
    rules: Rules,
    station_id: int | None = None,
    user_id: int | None = None,
    on_stored: Callable[[Session, TypeAssessmentRecord], None] | None = None,
) -> TypeAssessmentRecord:
    """Assess the model from its inspections and store inputs and results in one transaction.

    `on_stored(session, record)` runs once the record has its id, before the commit (the page's
    one-time form token is kept in the same transaction).
    """
    inspections = inspections_for(session, request, station_id=station_id)
    try:
        result = assess_type([member(i, rules) for i in inspections])
    except StabilityError as error:
        raise refusal(error) from error
    begin_write(session)
    record = _record(request, inspections, result, station_id=station_id, user_id=user_id)
    session.add(record)
    session.flush()
    if on_stored is not None:
        on_stored(session, record)
    session.commit()
    return record


def _record(
    request: TypeRequest,
    inspections: Sequence[Inspection],
    result: TypeAssessment,
    *,
    station_id: int | None,
    user_id: int | None,
) -> TypeAssessmentRecord:
    first = result.members[0].data
    table = result.table
    return TypeAssessmentRecord(
        created_at=utcnow(),
        station_id=station_id,
        user_id=user_id,
        make=inspections[0].vehicle.make,
        model=inspections[0].vehicle.model,
        model_year=request.model_year,
        rules_version=type_rules_version(table.layout),
        occupant_mass_kg=table.occupant_mass_kg,
        wheelbase_m=first.wheelbase_m,
        occupant_config={
            "seats": [{"role": s.role, "x_m": str(s.x_m)} for s in first.seats],
            "load_items": [
                {"label": i.label, "mass_kg": str(i.mass_kg), "x_m": str(i.x_m)} for i in first.load_items
            ],
        },
        confidence=CONFIDENCE,
        t_value=result.spread[0].t,
        vehicle_count=len(inspections),
        compliant=result.compliant,
        max_compliant_occupants=result.max_compliant_occupants,
        members=[
            TypeAssessmentInspection(position=position, inspection_id=inspection.id, inspection=inspection)
            for position, inspection in enumerate(inspections)
        ],
        cases=[
            TypeAssessmentCase(
                occupants=row.occupants,
                total_kg=quantize(row.total_kg, 6),
                rear_kg=quantize(row.rear_kg, 6),
                lsf=quantize(row.lsf, 8),
                variance=quantize(row.variance, 8),
                compliant=row.compliant,
                lsf_exact=f"{row.lsf.numerator}/{row.lsf.denominator}",
                min_lsf=quantize(spread.min_lsf, 8),
                mean_lsf=quantize(spread.mean_lsf, 8),
                max_lsf=quantize(spread.max_lsf, 8),
                sd_lsf=round(spread.sd_lsf, 8),
                upper_95_lsf=round(spread.upper_95_lsf, 8),
                confident_compliant=spread.confident_compliant,
            )
            for row, spread in zip(table.cases, result.spread, strict=True)
        ],
    )


def get_type_assessment(
    session: Session, assessment_id: int, *, station_id: int | None = None
) -> TypeAssessmentRecord:
    """The stored type assessment, or NotFound; a station reads only the ones it asked for."""
    record = session.get(TypeAssessmentRecord, assessment_id)
    if record is None or (station_id is not None and record.station_id != station_id):
        raise NotFound(
            f"type_assessment_id: type assessment {assessment_id} does not exist",
            field="type_assessment_id",
            rule="exists",
        )
    return record


def latest_type_assessments(session: Session) -> dict[tuple[str, str], TypeAssessmentRecord]:
    """The newest type assessment of each make and model (any model year), keyed by lower-case names."""
    records = session.scalars(
        select(TypeAssessmentRecord).order_by(TypeAssessmentRecord.created_at, TypeAssessmentRecord.id)
    ).all()
    return {(r.make.strip().lower(), r.model.strip().lower()): r for r in records}


@dataclass(frozen=True)
class KnownModel:
    """A make, model and model year on file, with how many of its vehicles have been inspected."""

    make: str
    model: str
    model_year: int | None
    vehicles_inspected: int


def known_models(session: Session, *, limit: int = 200) -> list[KnownModel]:
    """The models whose vehicles have inspections, most inspected vehicles first."""
    inspected = func.count(func.distinct(Inspection.vehicle_id))
    rows = session.execute(
        select(Vehicle.make, Vehicle.model, Vehicle.model_year, inspected)
        .join(Inspection, Inspection.vehicle_id == Vehicle.id)
        .group_by(Vehicle.make, Vehicle.model, Vehicle.model_year)
        .order_by(inspected.desc(), Vehicle.make, Vehicle.model, Vehicle.model_year)
        .limit(limit)
    ).all()
    return [KnownModel(make, model, year, count) for make, model, year, count in rows]
