"""Record an inspection: assess it with the pure core and store every reading and case for good."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from datetime import date, datetime
from decimal import Decimal
from functools import lru_cache
from typing import Any, Protocol, TypeVar

from sqlalchemy import ColumnElement, Select, bindparam, func, select
from sqlalchemy.orm import Session

from app.db import begin_write, utcnow
from app.dynamics.estimates import CgLift, checked_dynamics, estimate_inputs
from app.dynamics.service import current_revision
from app.errors import InvalidInput, NotFound
from app.inspections.models import Inspection
from app.inspections.record import InspectionRecord, Provenance, new_record
from app.inspections.store import store_record
from app.stability import (
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
from app.stability.dynamics import Dynamics
from app.stations.models import Station
from app.stations.on_file import StationOnFile
from app.stations.scale import (
    ScaleRules,
    check_calibration,
    check_capacity,
    check_settled,
    configured_scale_rules,
)
from app.vehicles.models import Vehicle
from app.vehicles.on_file import VehicleOnFile
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
    # For the estimates beyond the static test (app/dynamics/estimates.py): one or neither.
    cg_lift: CgLift | None = None
    cg_height_m: Decimal | None = None


def build_input(vehicle: VehicleOnFile, request: InspectionRequest) -> AssessmentInput:
    """The pure core's input, filling what the request leaves out from the vehicle's record."""
    return AssessmentInput(
        readings=request.readings,
        wheelbase_m=request.wheelbase_m if request.wheelbase_m is not None else vehicle.wheelbase_m,
        seats=request.seats or vehicle.seats,
        load_items=request.load_items,
        measured_cases=request.measured_cases,
        occupant_mass_kg=request.occupant_mass_kg,
        layout=vehicle.layout,
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


@dataclass(frozen=True)
class Decided:
    """An inspection decided and rounded as it will be stored, with its estimates."""

    record: InspectionRecord
    estimates: Dynamics


def decide(
    request: InspectionRequest,
    *,
    vehicle: VehicleOnFile,
    station: StationOnFile | None,
    rules: Rules,
    scale_rules: ScaleRules,
    user_id: int | None = None,
    today: date | None = None,
) -> Decided:
    """Check the scale, assess exactly, check the estimates' inputs, and round the record once (no I/O).

    A station's scale must be calibrated on `today` (UTC) and every reading within its capacity;
    repeated readings must agree within `scale_rules`. Every refusal is a ServiceError naming the field.
    """
    now = utcnow()
    check_scale(request, station=station, rules=scale_rules, today=today or now.date())
    data = build_input(vehicle, request)
    result = assess_input(data, rules)
    estimate_columns = estimate_inputs(
        cg_lift=request.cg_lift,
        cg_height_m=request.cg_height_m,
        seats=request.seats,
        vehicle_seats=vehicle.seats,
        figures=vehicle.figures,
    )
    record = new_record(
        data=data,
        result=result,
        rules=rules,
        provenance=Provenance(
            vehicle_id=vehicle.id,
            registration_number=vehicle.registration_number,
            station_id=station.id if station else None,
            station_name=station.name if station else None,
            calibration_certificate=station.calibration_certificate if station else None,
            calibration_valid_until=station.calibration_valid_until if station else None,
            user_id=user_id,
        ),
        measured_cases=request.measured_cases,
        load_items=request.load_items,
        dynamics_revision_id=vehicle.figures_revision_id,
        dynamics_input=estimate_columns,
        created_at=now,
    )
    return Decided(record, checked_dynamics(record, vehicle.figures))


def record_inspection(
    session: Session,
    *,
    request: InspectionRequest,
    rules: Rules,
    station: Station | None = None,
    user_id: int | None = None,
    on_stored: Callable[[Session, int], None] | None = None,
    scale_rules: ScaleRules | None = None,
    today: date | None = None,
) -> Inspection:
    """Assess and store one inspection in a single transaction; nothing is stored if it is refused.

    The officers' pages and the command line take this door; the stations' API takes the same steps
    in `app.inspections.submission`. `on_stored(session, inspection_id)` runs once the inspection
    has its id, before the commit, so a caller can store a row of its own in the same transaction
    (the pages' one-time form token).
    """
    found = get_vehicle(session, request.registration_number)
    vehicle = VehicleOnFile.of(found, current_revision(session, found.id))
    decided = decide(
        request,
        vehicle=vehicle,
        station=StationOnFile.of(station) if station else None,
        rules=rules,
        scale_rules=scale_rules or configured_scale_rules(),
        user_id=user_id,
        today=today,
    )
    begin_write(session)  # SQLite: only the inserts and the commit take the writer's turn
    inspection_id = store_record(session.connection(), decided.record)
    if on_stored is not None:
        on_stored(session, inspection_id)
    session.commit()
    inspection = session.get(Inspection, inspection_id)
    assert inspection is not None
    return inspection


def reading_sets(request: InspectionRequest) -> list[tuple[str, WheelReadings]]:
    """Every set of readings in a request with the API path of its field: the base weighing first."""
    return [("readings", request.readings)] + [
        (f"measured_cases[{index}].readings", measured.readings)
        for index, measured in enumerate(request.measured_cases)
    ]


def check_scale(
    request: InspectionRequest, *, station: StationOnFile | None, rules: ScaleRules, today: date
) -> None:
    """Refuse readings from a station scale out of calibration or beyond capacity, or not settled."""
    sets = reading_sets(request)
    if station is not None:
        check_calibration(station, today=today, rules=rules)
        check_capacity(station, sets)
    check_settled(sets, rules=rules, division_kg=station.division_kg if station else None)


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


@dataclass(frozen=True)
class ListedInspection:
    """An inspection as a list shows it: when, which vehicle, where, and the verdict."""

    id: int
    created_at: datetime
    compliant: bool
    max_compliant_occupants: int
    registration_number: str
    registration_key: str
    station_name: str | None


def list_inspections(
    session: Session, *, where: InspectionFilter, limit: int, offset: int
) -> tuple[list[ListedInspection], int]:
    """One page of inspections matching the filter, newest first, and how many match in all.

    The page reads only the columns a list shows (no inspection, vehicle or station is loaded as
    an object); the count is `count_inspections`.
    """
    values = _filter_values(where)
    if values is None:
        return [], 0
    names = tuple(values)
    page = session.execute(_page_query(names), values | {"limit": limit, "offset": offset}).all()
    listed = [ListedInspection(*row[:_SHOWN]) for row in page]
    if _names_a_vehicle(names) and page:  # counted by the page's scan (see _page_query)
        return listed, int(page[0].total)
    return listed, _count(session, where, values, now=utcnow())


def count_inspections(session: Session, *, where: InspectionFilter, now: datetime | None = None) -> int:
    """How many inspections match the filter.

    A vehicle's are counted from the records (a few hundred at most). Otherwise the closed days the
    period covers whole come from their stored counts and only its ends are counted
    (app/statistics/matching.py), so the count costs the same at any size of the history.
    """
    values = _filter_values(where)
    return 0 if values is None else _count(session, where, values, now=now or utcnow())


def _count(session: Session, where: InspectionFilter, values: dict[str, Any], *, now: datetime) -> int:
    names = tuple(values)
    if _names_a_vehicle(names):
        query = _from_inspections(select(func.count()).select_from(Inspection), names)
        return int(session.scalar(query.where(*_conditions(names)), values) or 0)
    return _match_counter(
        session,
        conditions=_conditions(names),
        values=values,
        since=where.since,
        until=where.until,
        compliant=where.compliant,
        station_id=where.station_id,
        now=now,
    )


class MatchCounter(Protocol):
    """Counts the inspections `conditions` match (on bound parameters `values`); `since`, `until`,
    `compliant` and `station_id` are the filter's own, `now` decides which days are closed."""

    def __call__(
        self,
        session: Session,
        *,
        conditions: Sequence[ColumnElement[bool]],
        values: Mapping[str, Any],
        since: datetime | None,
        until: datetime | None,
        compliant: bool | None,
        station_id: int | None,
        now: datetime,
    ) -> int: ...


def _count_from_records(
    session: Session,
    *,
    conditions: Sequence[ColumnElement[bool]],
    values: Mapping[str, Any],
    since: datetime | None,
    until: datetime | None,
    compliant: bool | None,
    station_id: int | None,
    now: datetime,
) -> int:
    query = select(func.count()).select_from(Inspection).where(*conditions)
    return int(session.scalar(query, dict(values)) or 0)


# The statistics package counts from its stored days (app/statistics/matching.py); it lies above this
# one, so the composition root passes its counter in (count_matches_with).
_match_counter: MatchCounter = _count_from_records


def count_matches_with(counter: MatchCounter) -> None:
    """Count the inspections a list's filter matches with `counter` from now on."""
    global _match_counter
    _match_counter = counter


_SHOWN = len(fields(ListedInspection))  # the page's first columns, after them its `total`


# Built once per filter shape (which values it has), on bound parameters: building the statement
# cost a vehicle's history as much as running it.
@lru_cache(maxsize=64)
def _page_query(names: tuple[str, ...]) -> Select[Any]:
    """A page (`limit` rows after `offset`) of the inspections matching the filter values `names`,
    newest first, with the columns of a ListedInspection and, for a vehicle's history, `total`."""
    # The page's rows are chosen from the inspections alone (joined to the vehicle only when the
    # filter names it; a vehicle's history is then read from its index alone), and only the chosen
    # rows are joined to their vehicle and station: a deep page skips its offset without a vehicle
    # look-up for every row it skips.
    columns: list[Any] = [
        Inspection.id,
        Inspection.created_at,
        Inspection.compliant,
        Inspection.max_compliant_occupants,
        Inspection.vehicle_id,
        Inspection.station_id,
    ]
    if _names_a_vehicle(names):  # a vehicle's history (a few hundred rows at most): counted by the scan
        columns.append(func.count().over().label("total"))
    chosen_rows = (
        _from_inspections(select(*columns), names)
        .where(*_conditions(names))
        .order_by(Inspection.created_at.desc(), Inspection.id.desc())
        .limit(bindparam("limit"))
        .offset(bindparam("offset"))
        .subquery()
    )
    shown = [
        chosen_rows.c.id,
        chosen_rows.c.created_at,
        chosen_rows.c.compliant,
        chosen_rows.c.max_compliant_occupants,
        Vehicle.registration_number,
        Vehicle.registration_key,
        Station.name,
    ]
    return (
        select(*shown, *([chosen_rows.c.total] if _names_a_vehicle(names) else []))
        .join(Vehicle, Vehicle.id == chosen_rows.c.vehicle_id)
        .outerjoin(Station, Station.id == chosen_rows.c.station_id)
        .order_by(chosen_rows.c.created_at.desc(), chosen_rows.c.id.desc())
    )


def _names_a_vehicle(names: tuple[str, ...]) -> bool:
    """Whether the filter values `names` name one vehicle (its condition is on the vehicle)."""
    return "registration_key" in names


_Query = TypeVar("_Query", bound="Select[*tuple[Any, ...]]")


def _from_inspections(query: _Query, names: tuple[str, ...]) -> _Query:
    """The query on inspections, with their vehicle joined when the filter names one (its condition
    is on the vehicle)."""
    return query.join(Vehicle, Vehicle.id == Inspection.vehicle_id) if _names_a_vehicle(names) else query


def _filter_values(where: InspectionFilter) -> dict[str, Any] | None:
    """The values the filter sets, by the name of their bound parameter; None when nothing can match."""
    values: dict[str, Any] = {}
    if where.registration_number:
        key = normalise_registration(where.registration_number)
        if not valid_key(key):  # no vehicle has it; and PostgreSQL cannot even compare a NUL
            return None
        values["registration_key"] = key
    if where.compliant is not None:
        values["compliant"] = where.compliant
    if where.station_id is not None:
        values["station_id"] = where.station_id
    if where.since is not None:
        values["since"] = where.since
    if where.until is not None:
        values["until"] = where.until
    return values


_CONDITIONS: dict[str, Callable[[], ColumnElement[bool]]] = {
    "registration_key": lambda: Vehicle.registration_key == bindparam("registration_key"),
    "compliant": lambda: Inspection.compliant == bindparam("compliant"),
    "station_id": lambda: Inspection.station_id == bindparam("station_id"),
    "since": lambda: Inspection.created_at >= bindparam("since"),
    "until": lambda: Inspection.created_at < bindparam("until"),
}


@lru_cache(maxsize=64)
def _conditions(names: tuple[str, ...]) -> tuple[ColumnElement[bool], ...]:
    """The SQL conditions on inspection (and vehicle) of the filter values `names`, on bound
    parameters of the same names."""
    return tuple(_CONDITIONS[name]() for name in names)
