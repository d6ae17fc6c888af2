"""Record an inspection: assess it with the pure core and store every reading and case for good."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from datetime import UTC, date, datetime
from decimal import ROUND_HALF_EVEN, ROUND_HALF_UP, Decimal
from fractions import Fraction
from operator import itemgetter
from typing import cast

from sqlalchemy import Table, func, select
from sqlalchemy.orm import Session, lazyload, make_transient_to_detached
from sqlalchemy.orm.attributes import set_committed_value

from app.db import begin_write, utcnow
from app.errors import InvalidInput, NotFound
from app.inspections.dynamics import CgLift, figures_for_inspection
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.stability import (
    RULES_VERSION,
    Assessment,
    AssessmentInput,
    LoadItem,
    MeasuredCase,
    Rules,
    Seat,
    StabilityError,
    WheelReadings,
    assess,
)
from app.stability.model import WHEELS
from app.stations.models import Station
from app.stations.scale import (
    ScaleRules,
    check_calibration,
    check_capacity,
    check_settled,
    configured_scale_rules,
)
from app.vehicles.models import Vehicle
from app.vehicles.service import get_vehicle, normalise_registration, valid_key


@dataclass(frozen=True)
class InspectionRequest:
    """What a door (API, form, CLI) hands the service: raw readings and optional overrides."""

    registration_number: str
    readings: WheelReadings
    wheelbase_m: Decimal | None = None
    occupant_mass_kg: Decimal | None = None
    seats: tuple[Seat, ...] | None = None
    load_items: tuple[LoadItem, ...] = ()
    measured_cases: tuple[MeasuredCase, ...] = field(default_factory=tuple)
    # For the estimates beyond the static test (app/inspections/dynamics.py): one or neither.
    cg_lift: CgLift | None = None
    cg_height_m: Decimal | None = None


def quantize(value: Fraction, places: int) -> Decimal:
    """An exact fraction rounded half-even to `places` decimals, for storage and display only."""
    exponent = Decimal(1).scaleb(-places)
    return (Decimal(value.numerator) / Decimal(value.denominator)).quantize(exponent, ROUND_HALF_EVEN)


def build_input(vehicle: Vehicle, request: InspectionRequest) -> AssessmentInput:
    """The pure core's input, filling what the request leaves out from the vehicle's record."""
    return AssessmentInput(
        readings=request.readings,
        wheelbase_m=request.wheelbase_m if request.wheelbase_m is not None else vehicle.wheelbase_m,
        seats=request.seats or tuple(Seat(s.role, s.x_m) for s in vehicle.seats),  # type: ignore[arg-type]
        load_items=request.load_items,
        measured_cases=request.measured_cases,
        occupant_mass_kg=request.occupant_mass_kg,
    )


def assess_input(data: AssessmentInput, rules: Rules) -> Assessment:
    """Run the pure core, turning its refusal into a 422 that names the field."""
    try:
        return assess(data, rules)
    except StabilityError as error:
        raise refusal(error) from error


def refusal(error: StabilityError) -> InvalidInput:
    """The core's refusal as a 422 whose message starts with the field's path, like every other one."""
    message = error.message
    if not message.startswith(f"{error.field}:"):
        message = f"{error.field}: {message}"
    return InvalidInput(message, field=error.field, rule=error.rule)


def record_inspection(
    session: Session,
    *,
    request: InspectionRequest,
    rules: Rules,
    station: Station | None = None,
    user_id: int | None = None,
    on_stored: Callable[[Session, Inspection], None] | None = None,
    scale_rules: ScaleRules | None = None,
    today: date | None = None,
) -> Inspection:
    """Assess and store one inspection in a single transaction; nothing is stored if it is refused.

    A station's scale must be calibrated on `today` (UTC) and every reading within its capacity;
    repeated readings must agree within `scale_rules` (None: the configured rules).
    `on_stored(session, inspection)` runs once the inspection has its id, before the commit, so a
    caller can store a row of its own in the same transaction (the pages' one-time form token, the
    API's idempotency key).
    """
    check_scale(request, station=station, rules=scale_rules or configured_scale_rules(), today=today)
    vehicle = get_vehicle(session, request.registration_number)
    data = build_input(vehicle, request)
    result = assess_input(data, rules)
    estimates = figures_for_inspection(
        session,
        vehicle=vehicle,
        result=result,
        cg_lift=request.cg_lift,
        cg_height_m=request.cg_height_m,
        seats=request.seats,
        has_load_items=bool(request.load_items),
    )
    begin_write(session)  # SQLite: only the inserts and the commit take the writer's turn
    columns: dict[str, object] = {
        "vehicle_id": vehicle.id,
        "station_id": station.id if station else None,
        "user_id": user_id,
        "created_at": utcnow(),
        "wheelbase_m": _scale(result.wheelbase_m, 4),
        "occupant_mass_kg": _scale(result.occupant_mass_kg, 3),
        "sum_tolerance": _scale(rules.sum_tolerance, 4),
        "rules_version": RULES_VERSION,
        "occupant_config": {
            "seats": [{"role": s.role, "x_m": str(s.x_m)} for s in data.seats],
            "load_items": [
                {"label": i.label, "mass_kg": str(i.mass_kg), "x_m": str(i.x_m)} for i in request.load_items
            ],
        },
        "front_kg": quantize(result.readings.front_kg, 4),
        "left_rear_kg": quantize(result.readings.left_rear_kg, 4),
        "right_rear_kg": quantize(result.readings.right_rear_kg, 4),
        "overall_kg": None if result.readings.overall_kg is None else quantize(result.readings.overall_kg, 4),
        "cg_from_front_m": quantize(result.cg_from_front_m, 5),
        "compliant": result.compliant,
        "max_compliant_occupants": result.max_compliant_occupants,
        "calibration_certificate": station.calibration_certificate if station else None,
        "calibration_valid_until": station.calibration_valid_until if station else None,
        **estimates.columns,
    }
    # Core INSERTs on the session's connection, in its transaction: the ORM's unit of work would
    # cost as much again in Python for rows that are written once and never changed.
    connection = session.connection()
    inspection_id = connection.execute(_INSERT_INSPECTION, columns).scalar_one()
    readings = _reading_rows(inspection_id, request)
    cases = _case_rows(inspection_id, result)
    connection.execute(_READING.insert(), readings)
    connection.execute(_CASE.insert(), cases)
    inspection = _as_stored(
        session, Inspection(id=inspection_id, **columns), vehicle, station, readings, cases
    )
    set_committed_value(inspection, "dynamics_revision", estimates.revision)
    if on_stored is not None:
        on_stored(session, inspection)
    session.commit()
    return inspection


# The tables themselves, for Core INSERTs (the mapped classes would take the ORM's bulk path).
_INSPECTION = cast(Table, Inspection.__table__)
_READING = cast(Table, Reading.__table__)
_CASE = cast(Table, LoadingCaseRow.__table__)
_INSERT_INSPECTION = _INSPECTION.insert().returning(_INSPECTION.c.id)


def _as_stored(
    session: Session,
    inspection: Inspection,
    vehicle: Vehicle,
    station: Station | None,
    readings: list[dict[str, object]],
    cases: list[dict[str, object]],
) -> Inspection:
    """The inspection just inserted, joined to the session as if loaded from it (nothing read back).

    It gets its vehicle, station, readings and cases in their relationships' order. Only the
    inspection joins the session's identity map: its rows are read through it, never changed.
    """
    make_transient_to_detached(inspection)
    session.add(inspection)
    set_committed_value(inspection, "vehicle", vehicle)
    set_committed_value(inspection, "station", station)
    in_order = sorted(readings, key=itemgetter("case_occupants", "wheel", "sequence"))
    set_committed_value(inspection, "readings", [Reading(**row) for row in in_order])
    by_occupants = sorted(cases, key=itemgetter("occupants"))
    set_committed_value(inspection, "loading_cases", [LoadingCaseRow(**row) for row in by_occupants])
    return inspection


def _scale(value: Decimal, places: int) -> Decimal:
    """A value at its column's scale, as the database gives it back (NUMERIC rounds half away from zero)."""
    return Decimal(value).quantize(Decimal(1).scaleb(-places), ROUND_HALF_UP)


def reading_sets(request: InspectionRequest) -> list[tuple[str, WheelReadings]]:
    """Every set of readings in a request with the API path of its field: the base weighing first."""
    return [("readings", request.readings)] + [
        (f"measured_cases[{index}].readings", measured.readings)
        for index, measured in enumerate(request.measured_cases)
    ]


def check_scale(
    request: InspectionRequest, *, station: Station | None, rules: ScaleRules, today: date | None = None
) -> None:
    """Refuse readings from a station scale out of calibration or beyond capacity, or not settled."""
    sets = reading_sets(request)
    if station is not None:
        check_calibration(station, today=today or datetime.now(UTC).date(), rules=rules)
        check_capacity(station, sets)
    check_settled(sets, rules=rules, division_kg=station.division_kg if station else None)


def _reading_rows(inspection_id: int, request: InspectionRequest) -> list[dict[str, object]]:
    """Every raw reading of the request as a row: the base weighing (case 0), then each measured case."""
    sets = [(0, request.readings)] + [(m.occupants, m.readings) for m in request.measured_cases]
    return [
        {
            "inspection_id": inspection_id,
            "case_occupants": case_occupants,
            "wheel": wheel,
            "sequence": i,
            "value_kg": _scale(value, 3),
        }
        for case_occupants, readings in sets
        for wheel in WHEELS
        for i, value in enumerate(readings.values(wheel))
    ]


def _case_rows(inspection_id: int, result: Assessment) -> list[dict[str, object]]:
    """Table 4 as rows: each loading case's exact values rounded for storage, and its exact LSF."""
    return [
        {
            "inspection_id": inspection_id,
            "occupants": case.occupants,
            "total_kg": quantize(case.total_kg, 6),
            "rear_kg": quantize(case.rear_kg, 6),
            "lsf": quantize(case.lsf, 8),
            "variance": quantize(case.variance, 8),
            "compliant": case.compliant,
            "measured": case.measured,
            "lsf_exact": f"{case.lsf.numerator}/{case.lsf.denominator}",
        }
        for case in result.cases
    ]


def get_inspection(session: Session, inspection_id: int, *, station_id: int | None = None) -> Inspection:
    """The inspection with this id, or NotFound; with `station_id`, only one that station submitted.

    Another station's inspection is answered exactly as one that does not exist.
    """
    inspection = session.get(Inspection, inspection_id)
    if inspection is None or (station_id is not None and inspection.station_id != station_id):
        raise NotFound(
            f"inspection_id: inspection {inspection_id} does not exist", field="inspection_id", rule="exists"
        )
    return inspection


@dataclass(frozen=True)
class InspectionFilter:
    """Which inspections a list shows."""

    registration_number: str | None = None
    compliant: bool | None = None
    station_id: int | None = None
    since: datetime | None = None
    until: datetime | None = None


def list_inspections(
    session: Session, *, where: InspectionFilter, limit: int, offset: int
) -> tuple[Sequence[Inspection], int]:
    """One page of inspections matching the filter, newest first, and how many match in all."""
    query = select(Inspection)
    if where.registration_number:
        key = normalise_registration(where.registration_number)
        if not valid_key(key):  # no vehicle has it; and PostgreSQL cannot even compare a NUL
            return [], 0
        query = query.join(Inspection.vehicle).where(Vehicle.registration_key == key)
    if where.compliant is not None:
        query = query.where(Inspection.compliant == where.compliant)
    if where.station_id is not None:
        query = query.where(Inspection.station_id == where.station_id)
    if where.since is not None:
        query = query.where(Inspection.created_at >= where.since)
    if where.until is not None:
        query = query.where(Inspection.created_at < where.until)
    total = session.scalar(select(func.count()).select_from(query.subquery())) or 0
    page = session.scalars(
        query.order_by(Inspection.created_at.desc(), Inspection.id.desc())
        .limit(limit)
        .offset(offset)
        # A list shows summaries: the readings and cases load only if a caller touches them.
        .options(lazyload(Inspection.readings), lazyload(Inspection.loading_cases))
    ).all()
    return page, total
