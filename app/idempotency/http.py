"""The Idempotency-Key header on the API's POSTs: answer a request once, replay that answer to retries.

Follows the IETF httpapi Idempotency-Key draft and Stripe's practice: keys are scoped per station;
a retry with the same key and body gets the first answer again (same status and body, plus
`Idempotent-Replayed: true`); a retry while the first still runs gets 409; the same key with another
body gets 422. Only a successful answer is stored, in the same transaction as what it created, so a
crash leaves neither; a refusal (4xx) or a server error (5xx) is not stored, and a retry is decided
afresh. Keys are kept at least TRIKECERT_IDEMPOTENCY_KEY_HOURS (24) hours, then pruned.
"""

from __future__ import annotations

from collections.abc import Callable
from datetime import timedelta
from typing import Annotated, Any

from fastapi import Header
from fastapi.responses import Response
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from app.api.errors import ErrorOut
from app.config import get_settings
from app.errors import ServiceError
from app.idempotency.service import (
    Claim,
    KeyInFlight,
    StoredAnswer,
    check_same_request,
    maybe_prune,
    remember,
    request_hash,
    stored_answer,
    try_lock,
)

REPLAYED_HEADER = "Idempotent-Replayed"
# 1 to 255 visible ASCII characters (no double quote), bare as Stripe takes them, or as the draft's
# structured-field string in double quotes, which are removed.
KEY_PATTERN = r'^(?:[\x21\x23-\x7e]{1,255}|"[\x21\x23-\x7e]{1,255}")$'
IdempotencyKeyHeader = Annotated[
    str | None,
    Header(
        alias="Idempotency-Key",
        pattern=KEY_PATTERN,
        description=(
            "Recommended: a fresh random key (a UUID) per weighing, sent again unchanged with every retry. "
            "The same key and body get the first answer replayed; a retry while the first is still "
            "running gets 409; the same key with another body gets 422. Keys are scoped to the station "
            "and kept at least 24 hours."
        ),
    ),
]

# Stores the body of the answer with the key, in the transaction that stores what it describes.
Remember = Callable[[bytes], None]


def idempotent_responses(status_code: int) -> dict[int | str, dict[str, Any]]:
    """OpenAPI entries: the replay header on the success status, and the 409 of a key still in flight."""
    return {
        status_code: {
            "headers": {
                REPLAYED_HEADER: {
                    "description": "`true` when this is the stored answer to an earlier request with the "
                    "same Idempotency-Key.",
                    "schema": {"type": "string", "enum": ["true"]},
                }
            }
        },
        409: {
            "model": ErrorOut,
            "description": "A request with the same Idempotency-Key is still being processed (retry "
            "after `Retry-After` seconds), or the request conflicts with a stored record.",
            "headers": {
                "Retry-After": {
                    "description": "Seconds to wait before retrying a key still in flight.",
                    "schema": {"type": "integer", "minimum": 1},
                }
            },
        },
    }


def key_of(header: str) -> str:
    """The key in an Idempotency-Key header (a structured-field string loses its quotes)."""
    return header[1:-1] if len(header) > 1 and header.startswith('"') and header.endswith('"') else header


def created(body: bytes) -> Response:
    """A 201 answer with this JSON body."""
    return _json(201, body)


def _json(status_code: int, body: bytes, *, replayed: bool = False) -> Response:
    headers = {REPLAYED_HEADER: "true"} if replayed else None
    return Response(content=body, status_code=status_code, media_type="application/json", headers=headers)


def replay(claim: Claim, stored: StoredAnswer) -> Response:
    """The stored answer again, marked as replayed; KeyReused (422) for a different request."""
    check_same_request(claim, stored)
    return _json(stored.status_code, stored.response_body.encode(), replayed=True)


def retention() -> timedelta:
    """How long a key and its answer are kept."""
    return timedelta(hours=get_settings().idempotency_key_hours)


def claim_of(header: str, *, station_id: int, operation: str, payload: Any) -> Claim:
    """The station's use of the key in the header for this operation and validated body."""
    return Claim(station_id, key_of(header), operation, request_hash(operation, payload))


def respond_once(
    session: Session,
    *,
    claim: Claim | None,
    status_code: int,
    perform: Callable[[Remember], bytes],
) -> Response:
    """Run `perform` once per station and key, and answer with the JSON body it returns.

    `perform(remember)` must call `remember(body)` before its commit with the body it returns, so
    the key and its answer are stored with the record they describe. Without a claim it simply runs.
    """
    if claim is None:
        return _json(status_code, perform(lambda _body: None))
    kept_for = retention()
    try:
        if not try_lock(session.connection(), claim):
            raise KeyInFlight()
        stored = stored_answer(session.connection(), claim, retention=kept_for)
        if stored is not None:
            return replay(claim, stored)

        def keep(body: bytes) -> None:
            remember(session.connection(), claim, status_code=status_code, body=body)

        try:
            body = perform(keep)
        except (ServiceError, IntegrityError):
            # A concurrent request with the same key may have committed first (SQLite waits for the
            # writer, then finds the key taken): answer with its stored response.
            session.rollback()
            stored = stored_answer(session.connection(), claim, retention=kept_for)
            if stored is None:
                raise
            return replay(claim, stored)
    finally:
        session.rollback()  # ends the transaction, releasing the advisory lock; a commit already happened
    maybe_prune(retention=kept_for)
    return _json(status_code, body)
