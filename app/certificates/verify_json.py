"""The public verification as JSON: for `Accept: application/json` on /verify/{number} and /V/{payload},
and for /api/v1/verify/{number}. No key, nothing about officers: only what the paper prints."""

from __future__ import annotations

from datetime import datetime

from sqlalchemy.orm import Session
from starlette.requests import Request
from starlette.responses import JSONResponse, Response

from app.api.errors import ErrorOut, FieldProblemOut
from app.certificates.answer_cache import kept_answer, verdict_until
from app.certificates.models import Certificate
from app.certificates.records import get_certificate
from app.certificates.schemas import VerificationOut
from app.certificates.verification import check_payload, verification_of
from app.config import get_settings
from app.errors import InvalidInput, ServiceError
from app.trust.claims import PayloadRefused
from app.trust.cwt import unverified_number
from app.trust.keys import published_keys
from app.trust.signing import query_values, verify_payload

JSON = "application/json"


def _quality(accept: str, media_type: str) -> float:
    """The q-value the Accept header gives this exact media type (0 when it is not named)."""
    for item in accept.split(","):
        name, *parameters = (part.strip() for part in item.split(";"))
        if name.lower() == media_type:
            for parameter in parameters:
                key, _, value = parameter.partition("=")
                if key.strip().lower() == "q":
                    try:
                        return float(value)
                    except ValueError:
                        return 0.0
            return 1.0
    return 0.0


def wants_json(request: Request) -> bool:
    """The client names application/json in Accept and does not prefer HTML."""
    return accepts_json(request.headers.get("accept", ""))


def accepts_json(accept: str) -> bool:
    """An Accept header that names application/json and does not prefer HTML."""
    json_q = _quality(accept, JSON)
    return json_q > 0 and json_q >= _quality(accept, "text/html")


def payload_param(request: Request) -> str | None:
    """The `p` query parameter read as sent: percent-decoded, but a '+' stays '+' (base45 has it)."""
    values = query_values(request.url.query, "p")
    return values[-1] if values else None


def verification(session: Session, certificate: Certificate, payload: str | None) -> VerificationOut:
    """The verification of a document, with the check of a scanned payload when one is given."""
    checked = None
    if payload is not None:
        checked = check_payload(payload, published_keys(session, get_settings()), certificate)
    return verification_of(certificate, checked)


def verification_json(session: Session, number: str, payload: str | None) -> Response:
    """The verification as a JSON answer (404 as JSON too); `Vary: Accept`: the address also serves HTML.
    Without a scanned payload, the answer kept while the records say nothing changed (answer_cache)."""
    if payload is not None:
        return _verification_json(session, number, payload)[0]
    return kept_answer("verify-json", number, lambda: _verification_json(session, number, None))


def _verification_json(
    session: Session, number: str, payload: str | None
) -> tuple[Response, datetime | None]:
    headers = {"Vary": "Accept", "Cache-Control": "no-store"}
    try:
        certificate = get_certificate(session, number)
    except ServiceError as error:
        return error_json(error, headers), None
    body = verification(session, certificate, payload).model_dump(mode="json", exclude_none=True)
    return JSONResponse(body, headers=headers), verdict_until(certificate)


def api_verification(session: Session, number: str, payload: str | None) -> Response:
    """/api/v1/verify/{number}'s answer (a number that finds nothing raises NotFound, answered as every
    API error is); without a payload, kept while the records say nothing changed."""

    def make() -> tuple[Response, datetime | None]:
        certificate = get_certificate(session, number)
        body = verification(session, certificate, payload).model_dump(mode="json", exclude_none=True)
        return JSONResponse(body), verdict_until(certificate)

    return make()[0] if payload is not None else kept_answer("api-verify", number, make)


def error_json(error: ServiceError, headers: dict[str, str] | None = None) -> JSONResponse:
    """A refusal in the API's error shape, `{detail, errors: [{field, rule, message}]}`."""
    problems = [FieldProblemOut(field=p.field, rule=p.rule, message=p.message) for p in error.problems]
    body = ErrorOut(detail=error.message, errors=problems).model_dump()
    return JSONResponse(body, status_code=error.status, headers=headers)


def number_of_payload(session: Session, payload: str) -> str:
    """The certificate number a scanned payload names: signed, or as claimed by a forgery to show its record.

    InvalidInput (field `payload`, the reason as rule) when no number can be read from it at all.
    """
    try:
        return verify_payload(payload, published_keys(session, get_settings())).claims.number
    except PayloadRefused as refused:
        number = unverified_number(payload)
        if number is None:
            raise InvalidInput(
                f"payload: this is not a certificate's QR code ({refused.message}); "
                "type the number printed on the paper at /verify",
                field="payload",
                rule=refused.reason,
            ) from refused
        return number
