"""Station API for vehicles: register one, look one up by registration."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, status

from app.api.errors import error_responses
from app.stations.deps import SessionDep, StationDep
from app.vehicles.models import Vehicle
from app.vehicles.schemas import (
    REGISTRATION_DESCRIPTION,
    REGISTRATION_PATTERN,
    SeatOut,
    VehicleIn,
    VehicleOut,
)
from app.vehicles.service import get_vehicle, register_vehicle

router = APIRouter(prefix="/vehicles", tags=["vehicles"])


def vehicle_out(vehicle: Vehicle) -> VehicleOut:
    """The API view of a stored vehicle."""
    return VehicleOut(
        id=vehicle.id,
        registration_number=vehicle.registration_number,
        make=vehicle.make,
        model=vehicle.model,
        model_year=vehicle.model_year,
        chassis_number=vehicle.chassis_number,
        wheelbase_m=float(vehicle.wheelbase_m),
        seats=[SeatOut(role=s.role, x_m=float(s.x_m)) for s in vehicle.seats],
        created_at=vehicle.created_at,
    )


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    response_model=VehicleOut,
    responses=error_responses(400, 401, 409, 413, 422),
    summary="Register a vehicle with its seat layout",
)
def create_vehicle(body: VehicleIn, session: SessionDep, _station: StationDep) -> VehicleOut:
    """Register a tricycle; a registration already on file (after normalising) answers 409."""
    vehicle = register_vehicle(
        session,
        registration_number=body.registration_number,
        make=body.make,
        model=body.model,
        model_year=body.model_year,
        chassis_number=body.chassis_number,
        wheelbase_m=body.wheelbase_m,
        seats=[(seat.role, seat.x_m) for seat in body.seats],
    )
    return vehicle_out(vehicle)


@router.get(
    "/{registration_number}",
    response_model=VehicleOut,
    responses=error_responses(401, 404, 422),
    summary="Find a vehicle by registration (case, spaces and hyphens ignored)",
)
def read_vehicle(
    registration_number: Annotated[
        str,
        Path(min_length=2, max_length=32, pattern=REGISTRATION_PATTERN, description=REGISTRATION_DESCRIPTION),
    ],
    session: SessionDep,
    _station: StationDep,
) -> VehicleOut:
    """The vehicle registered under this number; `bdg-252qh` finds `BDG 252 QH`."""
    return vehicle_out(get_vehicle(session, registration_number))
