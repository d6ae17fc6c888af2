"""Station API for vehicles: register one, look one up by registration."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, status
from fastapi.responses import Response
from sqlalchemy.orm import Session

from app.api.cross_field import cross_field_rules
from app.api.errors import error_responses
from app.api.strict_json import StrictJSONRoute
from app.dynamics.vehicle_api import dynamics_figures, dynamics_out
from app.idempotency.http import (
    IdempotencyKeyHeader,
    Remember,
    claim_of,
    idempotent_responses,
    respond_once,
)
from app.stations.deps import SessionDep, StationDep
from app.stations.rate_limit import RATE_LIMITED_RESPONSE
from app.vehicles.models import Vehicle
from app.vehicles.schemas import (
    RegistrationNumber,
    SeatOut,
    VehicleIn,
    VehicleOut,
)
from app.vehicles.service import get_vehicle, register_vehicle

router = APIRouter(prefix="/vehicles", tags=["vehicles"], route_class=StrictJSONRoute)


def vehicle_out(vehicle: Vehicle) -> VehicleOut:
    """The API view of a stored vehicle."""
    return VehicleOut(
        id=vehicle.id,
        registration_number=vehicle.registration_number,
        layout=vehicle.layout,
        make=vehicle.make,
        model=vehicle.model,
        model_year=vehicle.model_year,
        chassis_number=vehicle.chassis_number,
        wheelbase_m=float(vehicle.wheelbase_m),
        seats=[SeatOut(role=s.role, x_m=float(s.x_m)) for s in vehicle.seats],
        dynamics=dynamics_out(vehicle),
        created_at=vehicle.created_at,
    )


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    response_model=VehicleOut,
    responses={
        **error_responses(400, 401, 413, 422),
        **idempotent_responses(status.HTTP_201_CREATED),
        **RATE_LIMITED_RESPONSE,
    },
    summary="Register a vehicle with its seat layout",
)
@cross_field_rules("range", "front_track")
def create_vehicle(
    body: VehicleIn,
    session: SessionDep,
    station: StationDep,
    idempotency_key: IdempotencyKeyHeader = None,
) -> Response:
    """Register a tricycle; a registration already on file (after normalising) answers 409.

    With an `Idempotency-Key`, a retry of a registration that was stored gets its 201 replayed.
    """

    def perform(remember: Remember) -> bytes:
        answered: list[bytes] = []

        def on_stored(db: Session, vehicle: Vehicle) -> None:
            answered.append(vehicle_out(vehicle).model_dump_json().encode())
            remember(answered[0])

        register_vehicle(
            session,
            registration_number=body.registration_number,
            layout=body.layout,
            make=body.make,
            model=body.model,
            model_year=body.model_year,
            chassis_number=body.chassis_number,
            wheelbase_m=body.wheelbase_m,
            seats=[(seat.role, seat.x_m) for seat in body.seats],
            on_stored=on_stored,
            dynamics=dynamics_figures(body),
        )
        return answered[0]

    claim = None
    if idempotency_key is not None:
        claim = claim_of(
            idempotency_key,
            station_id=station.id,
            operation="POST /api/v1/vehicles",
            payload=body.model_dump(mode="json"),
        )
    return respond_once(session, claim=claim, status_code=status.HTTP_201_CREATED, perform=perform)


@router.get(
    "/{registration_number}",
    response_model=VehicleOut,
    responses={**error_responses(401, 404, 422), **RATE_LIMITED_RESPONSE},
    summary="Find a vehicle by registration (case, spaces and hyphens ignored)",
)
def read_vehicle(
    registration_number: Annotated[RegistrationNumber, Path()],
    session: SessionDep,
    _station: StationDep,
) -> VehicleOut:
    """The vehicle registered under this number; `bdg-252qh` finds `BDG 252 QH`."""
    return vehicle_out(get_vehicle(session, registration_number))
