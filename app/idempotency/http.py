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
from typing import Annotated, Any, Protocol

from fastapi import Header
from fastapi.responses import Response
from sqlalchemy import Connection
from sqlalchemy.exc import IntegrityError

from app.api.errors import ErrorOut
from app.config import get_settings
from app.db import begin_connection_transaction
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


class Transaction(Protocol):
    """Where the key is claimed and stored: a Session, or a Core connection (`OwnTransaction`)."""

    def connection(self) -> Connection:
        """The connection whose transaction holds the claim."""
        ...

    def rollback(self) -> None:
        """End the transaction (releasing the claim) if it is still open."""
        ...


class OwnTransaction:
    """A Core connection as a Transaction: it leaves autocommit, so a claim lasts until the commit."""

    def __init__(self, connection: Connection) -> None:
        begin_connection_transaction(connection)
        self._connection = connection

    def connection(self) -> Connection:
        """The connection itself."""
        return self._connection

    def rollback(self) -> None:
        """Roll back whatever is still open."""
        self._connection.rollback()


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


def _key(header: str) -> str:
    return header[1:-1] if len(header) > 1 and header.startswith('"') and header.endswith('"') else header


def created(body: bytes) -> Response:
    """A 201 answer with this JSON body."""
    return _json(201, body)


def _json(status_code: int, body: bytes, *, replayed: bool = False) -> Response:
    headers = {REPLAYED_HEADER: "true"} if replayed else None
    return Response(content=body, status_code=status_code, media_type="application/json", headers=headers)


def _replay(claim: Claim, stored: StoredAnswer) -> Response:
    check_same_request(claim, stored)
    return _json(stored.status_code, stored.response_body.encode(), replayed=True)


def claim_of(header: str, *, station_id: int, operation: str, payload: Any) -> Claim:
    """The station's use of the key in the header for this operation and validated body."""
    return Claim(station_id, _key(header), operation, request_hash(operation, payload))


def respond_once(
    transaction: Transaction,
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
    retention = timedelta(hours=get_settings().idempotency_key_hours)
    try:
        if not try_lock(transaction.connection(), claim):
            raise KeyInFlight()
        stored = stored_answer(transaction.connection(), claim, retention=retention)
        if stored is not None:
            return _replay(claim, stored)

        def keep(body: bytes) -> None:
            remember(transaction.connection(), claim, status_code=status_code, body=body)

        try:
            body = perform(keep)
        except (ServiceError, IntegrityError):
            # A concurrent request with the same key may have committed first (SQLite waits for the
            # writer, then finds the key taken): answer with its stored response.
            transaction.rollback()
            stored = stored_answer(transaction.connection(), claim, retention=retention)
            if stored is None:
                raise
            return _replay(claim, stored)
    finally:
        transaction.rollback()  # ends the transaction, releasing the advisory lock; a commit already happened
    maybe_prune(retention=retention)
    return _json(status_code, body)
