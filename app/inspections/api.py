"""Station API for inspections: submit readings and get Table 4 back at once; list and read them."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Body, Query, Request, status
from fastapi.responses import Response
from pydantic import PlainValidator

from app.api.cross_field import cross_field_rules
from app.api.errors import error_responses
from app.api.fields import Timestamp
from app.api.ids import InspectionId
from app.api.openapi import REQUIRED_BODY, as_sent
from app.api.strict_json import StrictJSONRoute
from app.dynamics.estimates import inspection_dynamics
from app.idempotency.http import IdempotencyKeyHeader, idempotent_responses
from app.inspections.answer import inspection_answer
from app.inspections.record import record_of
from app.inspections.schemas import (
    InspectionIn,
    InspectionOut,
    InspectionPage,
    InspectionSummary,
)
from app.inspections.service import (
    InspectionFilter,
    ListedInspection,
    get_inspection,
    list_inspections,
)
from app.inspections.submission import submit_inspection
from app.stations.deps import BEARER_SCHEME, AuthorizationHeader, SessionDep, StationDep, bearer_key
from app.stations.rate_limit import RATE_LIMITED_RESPONSE
from app.vehicles.schemas import RegistrationNumber

# The body as parsed JSON: validated as InspectionIn in the handler, after the key is checked and counted.
SubmissionBody = Annotated[Any, PlainValidator(as_sent, json_schema_input_type=InspectionIn), Body()]
router = APIRouter(prefix="/inspections", tags=["inspections"], route_class=StrictJSONRoute)
# The stations' hot path alone, so the app can match it before any other route (app/composition.py).
submission_router = APIRouter(prefix="/inspections", tags=["inspections"], route_class=StrictJSONRoute)


def inspection_summary(listed: ListedInspection) -> InspectionSummary:
    """The list view of a stored inspection."""
    return InspectionSummary(
        id=listed.id,
        registration_number=listed.registration_number,
        station=listed.station_name,
        created_at=listed.created_at,
        compliant=listed.compliant,
        max_compliant_occupants=listed.max_compliant_occupants,
    )


@submission_router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    response_model=InspectionOut,
    responses={
        **error_responses(400, 401, 403, 404, 413, 422),
        **idempotent_responses(status.HTTP_201_CREATED),
        **RATE_LIMITED_RESPONSE,
    },
    summary="Submit weighbridge readings; answers with Table 4 and the verdict",
    # The key is read from the header and checked in the handler: the station's bearer scheme.
    openapi_extra={"security": [{BEARER_SCHEME: []}], **REQUIRED_BODY},
)
@cross_field_rules(
    "sum_tolerance",
    "missing",
    "extra_forbidden",
    "range",
    "duplicate",
    "spread",
    "front_wheel_lift",
    "rear_wheel_lift",
    "less_than_level",
    "below_wheelbase",
    "one_of",
)
def create_inspection(
    request: Request,
    document: SubmissionBody = None,
    authorization: AuthorizationHeader = None,
    idempotency_key: IdempotencyKeyHeader = None,
) -> Response:
    """Assess and store one weighing; without `occupants` the vehicle's seats and the standard mass apply.

    Send an `Idempotency-Key` so a retry over a dropped link is answered, never stored twice. 403 when
    the station scale's calibration has lapsed; 422 for a reading above the scale's capacity or
    repeated readings that spread more than allowed (the scale had not settled).
    """
    return submit_inspection(
        document,
        station_key=bearer_key(authorization),
        idempotency_key=idempotency_key,
        scope=request.scope,
    )


@router.get(
    "/{inspection_id}",
    response_model=InspectionOut,
    responses={**error_responses(401, 404, 422), **RATE_LIMITED_RESPONSE},
    summary="Read a stored inspection",
)
def read_inspection(
    inspection_id: InspectionId,
    session: SessionDep,
    station: StationDep,
) -> InspectionOut:
    """The inspection as decided when it was stored; a station reads only its own (others: 404)."""
    inspection = get_inspection(session, inspection_id, station_id=station.id)
    _inputs, estimates = inspection_dynamics(inspection)
    return inspection_answer(record_of(inspection), estimates)


@router.get(
    "",
    response_model=InspectionPage,
    responses={**error_responses(401, 422), **RATE_LIMITED_RESPONSE},
    summary="List this station's inspections, newest first",
)
def index_inspections(
    session: SessionDep,
    station: StationDep,
    registration_number: Annotated[RegistrationNumber | None, Query()] = None,
    compliant: bool | None = None,
    since: Annotated[
        Timestamp | None, Query(description="Only inspections at or after this time (RFC 3339, with zone).")
    ] = None,
    until: Annotated[
        Timestamp | None, Query(description="Only inspections before this time (RFC 3339, with zone).")
    ] = None,
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    offset: Annotated[int, Query(ge=0, le=10_000_000)] = 0,
) -> InspectionPage:
    """Only the inspections this station submitted; filter by registration (normalised), verdict and
    time; paginate with limit and offset."""
    items, total = list_inspections(
        session,
        where=InspectionFilter(registration_number, compliant, station.id, since, until),
        limit=limit,
        offset=offset,
    )
    summaries = [inspection_summary(i) for i in items]
    return InspectionPage(items=summaries, total=total, limit=limit, offset=offset)
