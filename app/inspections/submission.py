"""POST /api/v1/inspections, a station's weighing, from the validated body to the commit.

The steps of the rule, in order, on one pooled connection:

1. look up, in one round trip: the station holding the key (401 if none), its request counted
   against the rate limit (429 beyond it), and the vehicle with its seats and figures; only then is
   the body validated (422 naming the field), so every signed request counts;
2. with an Idempotency-Key, claim the key: a retry gets the first answer replayed;
3. the vehicle must be registered (404); decide with the pure core: the scale checked, every loading
   case assessed exactly, the estimates' inputs checked, the record rounded once (422 naming the
   field);
4. store the record (one statement on PostgreSQL, a transaction of its own) and the key's answer;
5. answer with the record just stored, in the same words a later GET gives.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

from fastapi import status
from fastapi.responses import Response

from app.api.validation import validated_body
from app.config import get_settings
from app.db import autocommit, begin_connection_write, get_engine
from app.idempotency.http import OwnTransaction, Remember, claim_of, created, respond_once
from app.inspections.answer import inspection_answer
from app.inspections.lookup import OnFile, look_up
from app.inspections.requests import inspection_request
from app.inspections.schemas import InspectionIn
from app.inspections.service import decide
from app.inspections.store import store_record
from app.stations.deps import unknown_key
from app.stations.on_file import StationOnFile
from app.stations.rate_limit import RateLimit, check_count, window_start
from app.stations.scale import configured_scale_rules
from app.stations.service import hash_key
from app.vehicles.on_file import VehicleOnFile
from app.vehicles.service import lookup_key, not_registered

OPERATION = "POST /api/v1/inspections"


def submit_inspection(document: Any, *, station_key: str, idempotency_key: str | None) -> Response:
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
        )
        station = _authenticated(on_file)
        if on_file.counted is not None:
            check_count(limit, on_file.counted.count, on_file.counted.window_start, now)
        body = validated_body(document, InspectionIn)

        def decide_and_store(remember: Remember) -> bytes:
            decided = decide(
                inspection_request(body),
                vehicle=_registered(on_file, body.registration_number),
                station=station,
                rules=settings.rules(),
                scale_rules=configured_scale_rules(),
            )
            begin_connection_write(connection)  # SQLite; PostgreSQL writes in one statement
            record = replace(decided.record, id=store_record(connection, decided.record))
            answer = inspection_answer(record, decided.estimates).model_dump_json().encode()
            remember(answer)
            connection.commit()
            return answer

        if idempotency_key is None:
            return created(decide_and_store(lambda _answer: None))
        claim = claim_of(
            idempotency_key, station_id=station.id, operation=OPERATION, payload=body.model_dump(mode="json")
        )
        # The claim holds until the commit: the connection leaves autocommit for one transaction.
        return respond_once(
            OwnTransaction(connection),
            claim=claim,
            status_code=status.HTTP_201_CREATED,
            perform=decide_and_store,
        )


def _registration_key(document: Any) -> str | None:
    """The lookup key of the body's registration, read before the body is validated (None: none)."""
    registration = document.get("registration_number") if isinstance(document, dict) else None
    return lookup_key(registration) if isinstance(registration, str) else None


def _authenticated(on_file: OnFile) -> StationOnFile:
    if on_file.station is None:
        raise unknown_key()
    return on_file.station


def _registered(on_file: OnFile, registration_number: str) -> VehicleOnFile:
    if on_file.vehicle is None:
        raise not_registered(registration_number)
    return on_file.vehicle
