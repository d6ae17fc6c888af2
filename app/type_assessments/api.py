"""Station API for type assessments: assess a make and model from stored inspections, read it back.

A station authenticates with its key, as for inspections, and sees only its own: it assesses a model
from the inspections it submitted and reads the type assessments it asked for (others answer 404).
Officers assess any inspections from the page "Assess a model".
"""

from __future__ import annotations

from decimal import Decimal

from fastapi import APIRouter, status

from app.api.cross_field import cross_field_rules
from app.api.errors import error_responses
from app.api.ids import TypeAssessmentId
from app.api.strict_json import StrictJSONRoute
from app.config import get_settings
from app.stations.deps import SessionDep, StationDep
from app.stations.rate_limit import RATE_LIMITED_RESPONSE
from app.type_assessments.models import TypeAssessmentRecord
from app.type_assessments.schemas import (
    TypeAssessmentIn,
    TypeAssessmentOut,
    TypeSpreadOut,
    TypeTableRowOut,
    TypeVehicleOut,
    VehicleCaseOut,
)
from app.type_assessments.service import TypeRequest, create_type_assessment, get_type_assessment

router = APIRouter(prefix="/type-assessments", tags=["type assessments"], route_class=StrictJSONRoute)


def _f(value: Decimal, places: int) -> float:
    return float(round(value, places))


def type_assessment_out(record: TypeAssessmentRecord) -> TypeAssessmentOut:
    """The API view of a stored type assessment, figures rounded for display, verdicts as stored."""
    return TypeAssessmentOut(
        id=record.id,
        vehicles=[
            TypeVehicleOut(
                registration_number=m.inspection.vehicle.registration_number,
                inspection_id=m.inspection_id,
                cases=[
                    VehicleCaseOut(occupants=c.occupants, lsf=_f(c.lsf, 5), compliant=c.compliant)
                    for c in m.inspection.loading_cases
                ],
            )
            for m in record.members
        ],
        table=[
            TypeTableRowOut(
                occupants=c.occupants,
                total_kg=_f(c.total_kg, 2),
                rear_kg=_f(c.rear_kg, 2),
                lsf=_f(c.lsf, 4),
                variance=_f(c.variance, 4),
                compliant=c.compliant,
            )
            for c in record.cases
        ],
        spread=[
            TypeSpreadOut(
                occupants=c.occupants,
                min_lsf=_f(c.min_lsf, 5),
                mean_lsf=_f(c.mean_lsf, 5),
                max_lsf=_f(c.max_lsf, 5),
                sd_lsf=_f(c.sd_lsf, 5),
                upper_95_lsf=_f(c.upper_95_lsf, 5),
                confident_compliant=c.confident_compliant,
            )
            for c in record.cases
        ],
        compliant=record.compliant,
        max_compliant_occupants=record.max_compliant_occupants,
    )


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    response_model=TypeAssessmentOut,
    responses={**error_responses(400, 401, 404, 413, 422), **RATE_LIMITED_RESPONSE},
    summary="Assess a make and model from two or more vehicles' inspections; stored for good",
)
@cross_field_rules("too_few", "same_model", "one_per_vehicle", "same_layout", "measured_cases")
def create(body: TypeAssessmentIn, session: SessionDep, station: StationDep) -> TypeAssessmentOut:
    """The type's Table 4 from the mean readings, each case's spread and the confident verdict.

    Without `inspection_ids`: the latest inspection this station submitted of every registered vehicle
    of that make and model (and model year, when given). The vehicles must share one seat layout,
    wheelbase and occupant mass (422 naming them). An inspection id that is not this station's is 404.
    """
    request = TypeRequest(
        make=body.make,
        model=body.model,
        model_year=body.model_year,
        inspection_ids=tuple(body.inspection_ids) if body.inspection_ids is not None else None,
    )
    record = create_type_assessment(
        session, request=request, rules=get_settings().rules(), station_id=station.id
    )
    return type_assessment_out(record)


@router.get(
    "/{type_assessment_id}",
    response_model=TypeAssessmentOut,
    responses={**error_responses(401, 404, 422), **RATE_LIMITED_RESPONSE},
    summary="Read a stored type assessment",
)
def read(type_assessment_id: TypeAssessmentId, session: SessionDep, station: StationDep) -> TypeAssessmentOut:
    """The type assessment as computed when it was stored; a station reads only its own (others: 404)."""
    return type_assessment_out(get_type_assessment(session, type_assessment_id, station_id=station.id))
