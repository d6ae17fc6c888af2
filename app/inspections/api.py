"""Station API for inspections: submit readings and get Table 4 back at once; list and read them."""

from __future__ import annotations

from decimal import Decimal
from typing import Annotated

from fastapi import APIRouter, Query, status
from fastapi.responses import Response
from pydantic import WithJsonSchema
from sqlalchemy.orm import Session

from app.api.errors import error_responses
from app.api.fields import Timestamp
from app.api.strict_json import StrictJSONRoute
from app.config import get_settings
from app.idempotency.http import IdempotencyKeyHeader, Remember, idempotent_responses, respond_once
from app.ids import InspectionId
from app.inspections.dynamics import CgLift
from app.inspections.dynamics_api import case_dynamics_out
from app.inspections.models import Inspection
from app.inspections.remedies import inspection_remedies
from app.inspections.remedy_schemas import RemediesOut, remedies_out
from app.inspections.schemas import (
    AveragedReadingsOut,
    CalibrationOut,
    InspectionIn,
    InspectionOut,
    InspectionPage,
    InspectionSummary,
    LoadingCaseOut,
    ReadingsIn,
    SettingsOut,
)
from app.inspections.service import (
    InspectionFilter,
    InspectionRequest,
    get_inspection,
    list_inspections,
    record_inspection,
)
from app.numbers import LIMITS, POSITION_SCHEMA
from app.stability import LoadItem, MeasuredCase, Seat, WheelReadings, case_label
from app.stations.deps import SessionDep, StationDep
from app.stations.rate_limit import RATE_LIMITED_RESPONSE
from app.vehicles.schemas import RegistrationNumber

router = APIRouter(prefix="/inspections", tags=["inspections"], route_class=StrictJSONRoute)


def wheel_readings(body: ReadingsIn) -> WheelReadings:
    """The core's readings from the API's."""
    return WheelReadings(
        front_kg=tuple(body.front_kg),
        left_rear_kg=tuple(body.left_rear_kg),
        right_rear_kg=tuple(body.right_rear_kg),
        overall_kg=tuple(body.overall_kg or ()),
    )


def inspection_request(body: InspectionIn) -> InspectionRequest:
    """The service's request from the API body."""
    occupants = body.occupants
    return InspectionRequest(
        registration_number=body.registration_number,
        readings=wheel_readings(body.readings),
        wheelbase_m=body.wheelbase_m,
        occupant_mass_kg=occupants.mass_kg if occupants else None,
        seats=tuple(Seat(s.role, s.x_m) for s in occupants.seats) if occupants and occupants.seats else None,
        load_items=tuple(LoadItem(i.mass_kg, i.x_m, i.label) for i in body.load_items),
        measured_cases=tuple(
            MeasuredCase(m.occupants, wheel_readings(m.readings)) for m in body.measured_cases
        ),
        cg_lift=CgLift(body.cg_lift.lift_height_m, tuple(body.cg_lift.front_kg)) if body.cg_lift else None,
        cg_height_m=body.cg_height_m,
    )


def _f(value: Decimal, places: int) -> float:
    return float(round(value, places))


def inspection_summary(inspection: Inspection) -> InspectionSummary:
    """The list view of a stored inspection."""
    return InspectionSummary(
        id=inspection.id,
        registration_number=inspection.vehicle.registration_number,
        station=inspection.station.name if inspection.station else None,
        created_at=inspection.created_at,
        compliant=inspection.compliant,
        max_compliant_occupants=inspection.max_compliant_occupants,
    )


def _spread(inspection: Inspection) -> dict[str, float]:
    """How far each wheel's repeated readings of the base weighing spread (max - min, kg)."""
    values: dict[str, list[Decimal]] = {}
    for reading in inspection.readings:
        if reading.case_occupants == 0:
            values.setdefault(reading.wheel, []).append(reading.value_kg)
    return {wheel: _f(max(kg) - min(kg), 3) for wheel, kg in values.items()}


def _calibration(inspection: Inspection) -> CalibrationOut | None:
    if inspection.calibration_certificate is None and inspection.calibration_valid_until is None:
        return None
    return CalibrationOut(
        certificate=inspection.calibration_certificate, valid_until=inspection.calibration_valid_until
    )


def inspection_out(inspection: Inspection) -> InspectionOut:
    """The full API view of a stored inspection, figures rounded for display, verdicts as stored."""
    raw: dict[str, list[float]] = {}
    for reading in inspection.readings:
        if reading.case_occupants == 0:
            raw.setdefault(reading.wheel, []).append(float(reading.value_kg))
    empty = inspection.loading_cases[0]
    config = inspection.occupant_config
    estimates, missing = case_dynamics_out(inspection)
    return InspectionOut(
        **inspection_summary(inspection).model_dump(),
        vehicle_id=inspection.vehicle_id,
        wheelbase_m=float(inspection.wheelbase_m),
        readings=AveragedReadingsOut(
            front_kg=_f(inspection.front_kg, 3),
            left_rear_kg=_f(inspection.left_rear_kg, 3),
            right_rear_kg=_f(inspection.right_rear_kg, 3),
            overall_kg=_f(inspection.overall_kg, 3) if inspection.overall_kg is not None else None,
            rear_kg=_f(inspection.left_rear_kg + inspection.right_rear_kg, 3),
            total_kg=_f(empty.total_kg, 3),
        ),
        raw_readings=raw,
        spread_kg=_spread(inspection),
        calibration=_calibration(inspection),
        seats=[{"role": s["role"], "x_m": float(s["x_m"])} for s in config["seats"]],
        load_items=[
            {"label": i["label"], "mass_kg": float(i["mass_kg"]), "x_m": float(i["x_m"])}
            for i in config["load_items"]
        ],
        settings=SettingsOut(
            occupant_mass_kg=float(inspection.occupant_mass_kg),
            sum_tolerance=float(inspection.sum_tolerance),
            rules_version=inspection.rules_version,
        ),
        cg_from_front_m=_f(inspection.cg_from_front_m, 4),
        loading_cases=[
            LoadingCaseOut(
                occupants=case.occupants,
                label=case_label(case.occupants),
                total_kg=_f(case.total_kg, 2),
                rear_kg=_f(case.rear_kg, 2),
                lsf=_f(case.lsf, 4),
                variance=_f(case.variance, 4),
                compliant=case.compliant,
                measured=case.measured,
                dynamics=figures,
            )
            for case, figures in zip(inspection.loading_cases, estimates, strict=True)
        ],
        dynamics_missing=missing,
    )


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    response_model=InspectionOut,
    responses={
        **error_responses(400, 401, 403, 404, 413, 422),
        **idempotent_responses(status.HTTP_201_CREATED),
        **RATE_LIMITED_RESPONSE,
    },
    summary="Submit weighbridge readings; answers with Table 4 and the verdict",
)
def create_inspection(
    body: InspectionIn,
    session: SessionDep,
    station: StationDep,
    idempotency_key: IdempotencyKeyHeader = None,
) -> Response:
    """Assess and store one weighing; without `occupants` the vehicle's seats and the standard mass apply.

    Send an `Idempotency-Key` so a retry over a dropped link is answered, never stored twice. 403 when
    the station scale's calibration has lapsed; 422 for a reading above the scale's capacity or
    repeated readings that spread more than allowed (the scale had not settled).
    """
    request = inspection_request(body)

    def perform(remember: Remember) -> bytes:
        answered: list[bytes] = []

        def on_stored(db: Session, inspection: Inspection) -> None:
            answered.append(inspection_out(inspection).model_dump_json().encode())
            remember(db, answered[0])

        record_inspection(
            session, request=request, rules=get_settings().rules(), station=station, on_stored=on_stored
        )
        return answered[0]

    return respond_once(
        session,
        station_id=station.id,
        header=idempotency_key,
        operation="POST /api/v1/inspections",
        payload=body.model_dump(mode="json"),
        status_code=status.HTTP_201_CREATED,
        perform=perform,
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
    return inspection_out(get_inspection(session, inspection_id, station_id=station.id))


@router.get(
    "/{inspection_id}/remedies",
    response_model=RemediesOut,
    responses={**error_responses(401, 404, 422), **RATE_LIMITED_RESPONSE},
    summary="What would make the vehicle comply: front ballast, seats forward, stiffer rear tyres",
)
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
