"""Station API for an inspection's remedies: what would make the vehicle comply, sized per case."""

from __future__ import annotations

from decimal import Decimal
from typing import Annotated

from fastapi import APIRouter, Query
from pydantic import BeforeValidator, WithJsonSchema

from app.api.cross_field import cross_field_rules
from app.api.errors import error_responses
from app.api.ids import InspectionId
from app.api.strict_json import StrictJSONRoute
from app.config import get_settings
from app.inspections.service import get_inspection
from app.numbers import LIMITS, POSITION_SCHEMA, ascii_number_text
from app.remedies.schemas import RemediesOut, remedies_out
from app.remedies.service import inspection_remedies
from app.stations.deps import SessionDep, StationDep
from app.stations.rate_limit import RATE_LIMITED_RESPONSE

# Mounted right after the inspections' own router (app/composition.py), where its route always was.
router = APIRouter(prefix="/inspections", tags=["inspections"], route_class=StrictJSONRoute)


@router.get(
    "/{inspection_id}/remedies",
    response_model=RemediesOut,
    responses={**error_responses(401, 404, 422), **RATE_LIMITED_RESPONSE},
    summary="What would make the vehicle comply: front ballast, seats forward, stiffer rear tyres",
)
@cross_field_rules("remedies_range")
def read_remedies(
    inspection_id: InspectionId,
    session: SessionDep,
    station: StationDep,
    target_occupants: Annotated[
        int | None,
        Query(
            ge=0, le=LIMITS.max_seats, description="Occupants to certify for (default: every seat filled)."
        ),
    ] = None,
    ballast_x_m: Annotated[
        Decimal | None,
        # A JSON number in the schema, as the body's positions are (the default Decimal schema
        # also admits any string).
        WithJsonSchema(POSITION_SCHEMA),
        BeforeValidator(ascii_number_text),
        Query(
            ge=-LIMITS.seat_reach_m,
            le=LIMITS.max_wheelbase_m + LIMITS.seat_reach_m,
            allow_inf_nan=False,
            description="Where the ballast sits, metres behind the front wheel centre (negative: ahead of "
            "it); default TRIKECERT_BALLAST_X_M.",
        ),
    ] = None,
) -> RemediesOut:
    """Each remedy sized for every loading case up to the target, from the stored readings (exact;
    advised figures rounded up so they suffice); every remedy null when the cases already comply.
    A station reads only its own inspections (others: 404); a target above the seats is a 422."""
    settings = get_settings()
    inspection = get_inspection(session, inspection_id, station_id=station.id)
    remedies = inspection_remedies(
        inspection,
        target_occupants=target_occupants,
        ballast_x_m=settings.ballast_x_m if ballast_x_m is None else ballast_x_m,
        rules=settings.rules(),
    )
    return remedies_out(remedies)
