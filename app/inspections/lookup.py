"""What a submission reads before it decides: the station holding the key, its request counted, and the
vehicle on file with its seats and latest figures.

On PostgreSQL that is one statement in autocommit (the rate-limit row is locked only while it runs):

    WITH station AS (SELECT ... FROM station WHERE key_hash = :key_hash AND active),
         counted AS (INSERT INTO station_rate_window ... SELECT station.id ... ON CONFLICT ... DO UPDATE
                     ... RETURNING request_count, window_start)
    SELECT station.*, counted.*, vehicle.* FROM station JOIN counted ON ...
    LEFT JOIN (vehicle LEFT JOIN seat LEFT JOIN its latest vehicle_dynamics_revision) ON true
    ORDER BY seat.position

one row per seat. SQLite reads the same SELECT without `counted`, and counts the request in a write
transaction of its own (its writer's turn), only when the key is a station's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from decimal import Decimal
from typing import Any, cast

from sqlalchemy import Connection, Table, bindparam, func, literal, select, true
from sqlalchemy.dialects import postgresql, sqlite

from app.dynamics.models import DYNAMICS_FIELDS, VehicleDynamicsRevision
from app.dynamics.service import DynamicsFigures
from app.group_commit import write_and_commit
from app.idempotency.service import ANSWER_COLUMNS, StoredAnswer
from app.idempotency.service import KEYS_TABLE as _KEYS
from app.prepared import PreparedCache
from app.stability import Seat, layout_named
from app.stations.models import Station, StationRateWindow
from app.stations.on_file import StationOnFile
from app.stations.rate_limit import on_conflict_count
from app.vehicles.models import Seat as SeatRow
from app.vehicles.models import Vehicle
from app.vehicles.on_file import VehicleOnFile


@dataclass(frozen=True)
class Counted:
    """This request's number in the station key's current window, and when that window opened."""

    count: int
    window_start: int


@dataclass(frozen=True)
class OnFile:
    """What the database holds for one submission; None where nothing matched."""

    station: StationOnFile | None  # None: no active station holds the key
    counted: Counted | None  # None: not counted (no station, or no rate limit)
    vehicle: VehicleOnFile | None  # None: no vehicle has the registration
    stored: StoredAnswer | None = None  # the answer already stored under the Idempotency-Key


_STATION = cast(Table, Station.__table__)
_VEHICLE = cast(Table, Vehicle.__table__)
_SEAT = cast(Table, SeatRow.__table__)
_REVISION = cast(Table, VehicleDynamicsRevision.__table__)
_RATE = cast(Table, StationRateWindow.__table__)
_STATION_COLUMNS = (
    "id",
    "name",
    "calibration_certificate",
    "calibration_valid_until",
    "capacity_kg",
    "division_kg",
)


def look_up(
    connection: Connection,
    *,
    key_hash: str,
    registration_key: str | None,
    window_start: int | None,
    idempotency_key: str | None,
) -> OnFile:
    """The station holding the key (counted in the window opened at `window_start`, unless None),
    the vehicle with this lookup key and the answer stored under the station's Idempotency-Key
    (None: match nothing)."""
    parameters = {
        "key_hash": key_hash,
        "registration_key": registration_key,
        "window_start": window_start,
        "idempotency_key": idempotency_key,
    }

    counted_here = window_start is not None and connection.dialect.name == "postgresql"
    statement = _COUNTED_HERE if counted_here else _NOT_COUNTED
    rows = statement(connection).execute(connection, parameters)
    if not rows:
        return OnFile(None, None, None)
    first = rows[0]
    station = StationOnFile(**{name: first[f"station_{name}"] for name in _STATION_COLUMNS})
    counted = None
    if counted_here:
        counted = Counted(first["request_count"], first["window_start"])
    elif window_start is not None:
        counted = _count_apart(connection, station.id, window_start)
    stored = None
    if first["stored_operation"] is not None:
        stored = StoredAnswer(**{name: first[f"stored_{name}"] for name in ANSWER_COLUMNS})
    return OnFile(station, counted, _vehicle(rows), stored)


def _vehicle(rows: Sequence[dict[str, Any]]) -> VehicleOnFile | None:
    first = rows[0]
    if first["vehicle_id"] is None:
        return None
    heights = first["seat_heights_m"] or []
    return VehicleOnFile(
        id=first["vehicle_id"],
        registration_number=first["registration_number"],
        wheelbase_m=first["wheelbase_m"],
        seats=tuple(Seat(row["seat_role"], row["seat_x_m"]) for row in rows if row["seat_role"] is not None),
        figures=DynamicsFigures(
            seat_heights_m=tuple(None if z is None else Decimal(z) for z in heights),
            **{name: first[name] for name in DYNAMICS_FIELDS},
        ),
        figures_revision_id=first["revision_id"],
        layout=layout_named(first["layout"]),
    )


def _count_apart(connection: Connection, station_id: int, window_start: int) -> Counted:
    """SQLite: count the request in a write transaction, committed at once (together with the other
    writes waiting for the writer's turn in this process)."""
    parameters = {"station_id": station_id, "window_start": window_start}
    [row] = write_and_commit(connection, lambda writer: _COUNT_APART(writer).execute(writer, parameters))
    return Counted(row["request_count"], row["window_start"])


def _statement(*, counted_here: bool) -> Any:
    """The look-up (built once per shape): one row per seat; with `counted_here`, the count too."""
    station = (
        select(*[_STATION.c[name].label(f"station_{name}") for name in _STATION_COLUMNS])
        .where(_STATION.c.key_hash == bindparam("key_hash"), _STATION.c.active)
        .cte("key_holder")
    )
    latest = (
        select(func.max(_REVISION.c.revision))
        .where(_REVISION.c.vehicle_id == _VEHICLE.c.id)
        .correlate(_VEHICLE)
        .scalar_subquery()
    )
    vehicle = (
        select(
            _VEHICLE.c.id.label("vehicle_id"),
            _VEHICLE.c.registration_number,
            _VEHICLE.c.wheelbase_m,
            _VEHICLE.c.layout,
            _SEAT.c.position.label("seat_position"),
            _SEAT.c.role.label("seat_role"),
            _SEAT.c.x_m.label("seat_x_m"),
            _REVISION.c.id.label("revision_id"),
            _REVISION.c.seat_heights_m,
            *[_REVISION.c[name] for name in DYNAMICS_FIELDS],
        )
        .select_from(_VEHICLE)
        .outerjoin(_SEAT, _SEAT.c.vehicle_id == _VEHICLE.c.id)
        .outerjoin(_REVISION, (_REVISION.c.vehicle_id == _VEHICLE.c.id) & (_REVISION.c.revision == latest))
        .where(_VEHICLE.c.registration_key == bindparam("registration_key"))
        .subquery("vehicle")
    )
    stored = (
        select(
            *[_KEYS.c[name].label(f"stored_{name}") for name in ANSWER_COLUMNS],
            _KEYS.c.station_id.label("stored_station_id"),
        )
        .where(_KEYS.c.key == bindparam("idempotency_key"))
        .subquery("stored")
    )
    columns: list[Any] = [station, vehicle, stored]
    query = (
        select(*columns)
        .select_from(station)
        .outerjoin(vehicle, true())
        .outerjoin(stored, stored.c.stored_station_id == station.c.station_id)
    )
    if counted_here:
        counted = on_conflict_count(
            postgresql.insert(StationRateWindow).from_select(
                ["station_id", "window_start", "request_count"],
                select(
                    station.c.station_id,
                    bindparam("window_start", type_=_RATE.c.window_start.type),
                    literal(1),
                ),
            ),
            _RATE.c.station_id,
        ).cte("request_counted")
        query = (
            select(*columns, counted.c.request_count, counted.c.window_start)
            .select_from(station)
            .join(counted, counted.c.station_id == station.c.station_id)
            .outerjoin(vehicle, true())
            .outerjoin(stored, stored.c.stored_station_id == station.c.station_id)
        )
    return query.order_by(vehicle.c.seat_position)


_COUNT_APART = PreparedCache(
    lambda _dialect: on_conflict_count(
        sqlite.insert(StationRateWindow).values(
            station_id=bindparam("station_id"),
            window_start=bindparam("window_start"),
            request_count=literal(1),
        )
    )
)
_COUNTED_HERE = PreparedCache(lambda _dialect: _statement(counted_here=True))
_NOT_COUNTED = PreparedCache(lambda _dialect: _statement(counted_here=False))
