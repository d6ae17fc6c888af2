"""Station API for the estimates beyond the static test: per case in the answer, and at a speed."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query

from app.api.errors import error_responses
from app.api.ids import InspectionId
from app.api.strict_json import StrictJSONRoute
from app.config import get_settings
from app.dynamics.estimates import inspection_dynamics, lift_inputs
from app.dynamics.lookups import get_inspection
from app.dynamics.rounding import case_figures, rounded
from app.dynamics.schemas import CaseAtSpeedOut, DynamicsInputsOut, DynamicsOut
from app.errors import InvalidInput
from app.stability import StabilityError, case_label
from app.stability.dynamics import G, at_speed
from app.stations.deps import SessionDep, StationDep
from app.stations.rate_limit import RATE_LIMITED_RESPONSE

router = APIRouter(prefix="/inspections", tags=["inspections"], route_class=StrictJSONRoute)


@router.get(
    "/{inspection_id}/dynamics",
    response_model=DynamicsOut,
    responses={**error_responses(401, 404, 422), **RATE_LIMITED_RESPONSE},
    summary="Estimates beyond the static test: rollover, critical speed and the LSF at a speed",
)
def read_dynamics(
    inspection_id: InspectionId,
    session: SessionDep,
    station: StationDep,
    speed_kmh: Annotated[
        float, Query(ge=0, le=200, allow_inf_nan=False, description="Road speed (km/h).", examples=[60])
    ] = 0.0,
    acceleration_ms2: Annotated[
        float,
        Query(
            ge=-10,
            le=10,
            allow_inf_nan=False,
            description="Forward acceleration (m/s²); braking is negative.",
            examples=[1.5],
        ),
    ] = 0.0,
) -> DynamicsOut:
    """Per loading case: CG height, rollover threshold, tilt angle, understeer margin and critical speed,
    and at `speed_kmh` and `acceleration_ms2` the LSF with drag (at the centre of pressure) and
    acceleration (at the CG) moving load rearward, and the speed at which drag alone uses up a
    compliant case's margin. Estimates from the inputs shown; the stored verdict never changes."""
    inspection = get_inspection(session, inspection_id, station_id=station.id)
    density = get_settings().air_density_kg_m3
    data, dynamics = inspection_dynamics(inspection)
    try:
        moving, missing_at_speed = at_speed(
            data, dynamics, speed_kmh=speed_kmh, acceleration_ms2=acceleration_ms2, air_density_kg_m3=density
        )
    except StabilityError as error:
        raise InvalidInput(error.message, field=error.field, rule=error.rule) from error
    revision = inspection.dynamics_revision
    vehicle = data.vehicle
    return DynamicsOut(
        inspection_id=inspection.id,
        speed_kmh=speed_kmh,
        acceleration_ms2=acceleration_ms2,
        inputs=DynamicsInputsOut(
            vehicle_revision=revision.revision if revision else None,
            track_m=vehicle.track_m,
            wheel_radius_m=vehicle.wheel_radius_m,
            seat_heights_m=list(vehicle.seat_heights_m),
            front_cornering_stiffness_n_per_rad=vehicle.front_cornering_stiffness_n_per_rad,
            rear_cornering_stiffness_n_per_rad=vehicle.rear_cornering_stiffness_n_per_rad,
            drag_area_m2=vehicle.drag_area_m2,
            centre_of_pressure_height_m=vehicle.centre_of_pressure_height_m,
            front_track_m=vehicle.front_track_m,
            **lift_inputs(data),
            empty_cg_height_m=rounded(dynamics.empty_cg_height_m, 4),
            air_density_kg_m3=density,
            g_ms2=G,
        ),
        missing=list(dict.fromkeys([*dynamics.missing, *missing_at_speed])),
        loading_cases=[
            CaseAtSpeedOut(
                occupants=row.occupants,
                label=case_label(row.occupants),
                lsf=round(float(row.lsf), 4),
                compliant=row.compliant,
                **case_figures(figures),
                lsf_at_speed=rounded(speed.lsf_at_speed, 4),
                compliant_at_speed=speed.compliant_at_speed,
                margin_speed_kmh=rounded(speed.margin_speed_kmh, 1),
            )
            for row, figures, speed in zip(inspection.loading_cases, dynamics.cases, moving, strict=True)
        ],
    )
