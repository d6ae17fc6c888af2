"""POST /api/v1/inspections, a station's weighing, from the parsed body to the commit.

The steps of the rule, in order, on one pooled connection:

1. look up, in one round trip: the station holding the key (401 if none, 429 once the client's
   address sent too many keys no station holds: app.stations.deps.refused_key), its request counted
   against the rate limit (429 beyond it), the vehicle with its seats and figures, and the answer
   stored under the Idempotency-Key; only then is the body validated (422 naming the field), so
   every signed request counts;
2. with an Idempotency-Key already answered: that answer, replayed;
3. the vehicle must be registered (404); decide with the pure core: the scale checked, every loading
   case assessed exactly, the estimates' inputs checked, the record rounded once (422 naming the
   field);
4. store the record, and the answer kept under the key: on PostgreSQL one statement, a transaction
   of its own (with a key, the inspection's id is drawn just before, so the kept answer is complete,
   and the key's lock is taken in the same statement: 409 if another request holds it); on SQLite in
   the writer's turn, committed together with the other submissions waiting for it in the process
   (app/group_commit.py). A key stored meanwhile by a concurrent request: its answer;
5. answer with the record just stored, in the same words a later GET gives.
"""

from __future__ import annotations

import re
import time
from dataclasses import replace
from typing import Any

from fastapi import status
from fastapi.responses import Response
from sqlalchemy.exc import IntegrityError
from starlette.types import Scope

from app.api.validation import validated_body
from app.api.windows import RateLimit, window_start
from app.config import get_settings
from app.db import autocommit, get_engine
from app.errors import InvalidInput
from app.group_commit import write_and_commit
from app.idempotency.http import claim_of, created, key_of, replay, retention
from app.idempotency.service import maybe_prune, stored_answer, unless_expired
from app.inspections.answer import inspection_answer
from app.inspections.lookup import OnFile, look_up
from app.inspections.record import InspectionRecord
from app.inspections.requests import inspection_request
from app.inspections.schemas import InspectionIn
from app.inspections.service import decide
from app.inspections.store import KeptAnswer, draw_inspection_id, store_record
from app.stations.deps import refused_key
from app.stations.on_file import StationOnFile
from app.stations.rate_limit import check_count
from app.stations.scale import configured_scale_rules
from app.stations.service import hash_key
from app.vehicles.on_file import VehicleOnFile
from app.vehicles.service import lookup_key, not_registered

OPERATION = "POST /api/v1/inspections"


def submit_inspection(
    document: Any, *, station_key: str, idempotency_key: str | None, scope: Scope
) -> Response:
    """Assess and store one weighing (the body as parsed JSON); the answer is Table 4 and the verdict
    (201), or a refusal."""
    settings = get_settings()
    limit = RateLimit(settings.station_rate_limit, settings.station_rate_window_seconds)
    now = time.time()
    with get_engine().connect() as connection:
        autocommit(connection)
        on_file = look_up(
            connection,
            key_hash=hash_key(station_key),
            registration_key=_registration_key(document),
            window_start=window_start(limit, now) if limit.limit > 0 else None,
            idempotency_key=key_of(idempotency_key) if idempotency_key else None,
        )
        station = _authenticated(on_file, scope)
        if on_file.counted is not None:
            check_count(limit, on_file.counted.count, on_file.counted.window_start, now)
        body = validated_body(document, InspectionIn)

        claim = None
        if idempotency_key is not None:
            payload = _payload(body)
            claim = claim_of(idempotency_key, station_id=station.id, operation=OPERATION, payload=payload)
            if on_file.stored is not None:
                stored = unless_expired(connection, claim, on_file.stored, retention=retention())
                if stored is not None:
                    return replay(claim, stored)

        vehicle = _registered(on_file, body.registration_number)
        try:
            decided = decide(
                inspection_request(body),
                vehicle=vehicle,
                station=station,
                rules=settings.rules(),
                scale_rules=configured_scale_rules(),
            )
        except InvalidInput as error:
            raise _wheel_refusal(error, vehicle) from error
        answers: list[bytes] = []

        def answer(record: InspectionRecord) -> bytes:
            """The answer to this submission, made once (kept with the key, and sent)."""
            if not answers:
                answers.append(inspection_answer(record, decided.estimates).model_dump_json().encode())
            return answers[0]

        record, keep = decided.record, None
        if claim is not None:
            # The id before the write (PostgreSQL), so the answer kept with the key is complete.
            record = replace(record, id=draw_inspection_id(connection))
            keep = KeptAnswer(claim, status.HTTP_201_CREATED, answer)
        try:
            inspection_id = write_and_commit(
                connection, lambda writer: store_record(writer, record, keep=keep)
            )
        except IntegrityError:
            connection.rollback()
            if claim is None:
                raise
            # A request with the same key stored first (SQLite waited for its writer's turn): its answer.
            stored = stored_answer(connection, claim, retention=retention())
            if stored is None:
                raise
            return replay(claim, stored)
        if claim is not None:
            maybe_prune(retention=retention())
        return created(answer(replace(record, id=inspection_id)))


# The wheels added with the other layouts: left out of a body's payload when not sent, so a delta's
# Idempotency-Key stored before they existed still matches the same body sent again.
_LAYOUT_WHEELS = ("left_front_kg", "right_front_kg", "rear_kg")


def _payload(body: InspectionIn) -> dict[str, Any]:
    """The body as its Idempotency-Key remembers it."""
    payload: dict[str, Any] = body.model_dump(mode="json")
    for readings in [payload["readings"], *(case["readings"] for case in payload["measured_cases"])]:
        for wheel in _LAYOUT_WHEELS:
            if readings.get(wheel) is None:
                readings.pop(wheel, None)
    return payload


_WHEEL_FIELD = re.compile(r"^(measured_cases\[\d+\]\.)?readings\.\w+_kg$")


def _wheel_refusal(error: InvalidInput, vehicle: VehicleOnFile) -> InvalidInput:
    """A wheel of the vehicle's layout left out of the body, or one of another layout sent: refused
    with the API's rules for a key missing (`missing`) or not allowed (`extra_forbidden`), naming the
    vehicle's layout and its wheels.

    The schema cannot decide either, as the wheels depend on the vehicle; an empty list is refused by
    the schema, so the core's `required` here always means the key was not sent.
    """
    problem = error.problems[0] if error.problems else None
    field = problem.field if problem is not None else None
    if problem is None or field is None or not _WHEEL_FIELD.match(field):
        return error
    layout = vehicle.layout
    if problem.rule == "not_in_layout":
        return InvalidInput(problem.message, field=field, rule="extra_forbidden")
    if problem.rule != "required":
        return error
    return InvalidInput(
        f"{field}: required: a {layout.name} vehicle ({layout.description}) is weighed on "
        f"{', '.join(layout.wheels)}",
        field=field,
        rule="missing",
    )


def _registration_key(document: Any) -> str | None:
    """The lookup key of the body's registration, read before the body is validated (None: none)."""
    registration = document.get("registration_number") if isinstance(document, dict) else None
    return lookup_key(registration) if isinstance(registration, str) else None


def _authenticated(on_file: OnFile, scope: Scope) -> StationOnFile:
    if on_file.station is None:
        raise refused_key(scope)
    return on_file.station


def _registered(on_file: OnFile, registration_number: str) -> VehicleOnFile:
    if on_file.vehicle is None:
        raise not_registered(registration_number)
    return on_file.vehicle
