"""Every refusal as JSON `{detail, errors: [{field, rule, message}]}`; never a bare 500 for bad input."""

from __future__ import annotations

import logging
import re
from collections.abc import Sequence
from functools import lru_cache
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel
from sqlalchemy import exc as sa_exc
from starlette.exceptions import HTTPException as StarletteHTTPException

from app.db import RETRY_AFTER_SECONDS, is_outage
from app.errors import ServiceError

outage_log = logging.getLogger("trikecert.database")
# The database errors that may mean an outage; `is_outage` decides, the rest stay 500s.
DATABASE_ERRORS: tuple[type[Exception], ...] = (
    sa_exc.DBAPIError,
    sa_exc.TimeoutError,
    sa_exc.DisconnectionError,
)


class FieldProblemOut(BaseModel):
    """One refused field."""

    field: str
    rule: str
    message: str


class ErrorOut(BaseModel):
    """The body of every 4xx answer."""

    detail: str
    errors: list[FieldProblemOut] = []


def error_responses(*statuses: int) -> dict[int | str, dict[str, Any]]:
    """OpenAPI `responses` entries documenting the error body for these statuses."""
    return {status: {"model": ErrorOut} for status in statuses}


def field_path(loc: Sequence[int | str], body: Any = None) -> str:
    """('body', 'readings', 'front_kg', 0) -> 'readings.front_kg[0]'.

    A reading may be one number or a list; the API validates both as a list, so an index into a
    value that was sent as a single number is dropped: `readings.front_kg`, not `readings.front_kg[0]`.
    """
    in_body = bool(loc) and loc[0] == "body"
    parts = list(loc[1:]) if loc and loc[0] in ("body", "query", "path", "header") else list(loc)
    path = ""
    node = body if in_body else None
    for part in parts:
        if isinstance(part, int):
            if in_body and not isinstance(node, list):
                continue
            path += f"[{part}]"
        else:
            path += f".{part}" if path else str(part)
        node = _child(node, part)
    return path or (str(loc[0]) if loc else "body")


def _child(node: Any, part: int | str) -> Any:
    if isinstance(node, dict) and isinstance(part, str):
        return node.get(part)
    if isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
        return node[part]
    return None


def _problem(error: dict[str, Any], body: Any = None) -> FieldProblemOut:
    field = field_path(error.get("loc", ()), body)
    message = str(error.get("msg", "invalid value"))
    if message.startswith("Value error, "):
        message = message.removeprefix("Value error, ")
    rule = str(error.get("type", "invalid"))
    if rule == "extra_forbidden":
        message = "this field is not part of the API; remove it (names are case-sensitive)"
    if field == "body" and rule in ("missing", "model_attributes_type"):
        message = "send one JSON object, with Content-Type: application/json"
    if rule == "json_invalid":
        return FieldProblemOut(
            field="body", rule=rule, message=f"body: the request is not valid JSON ({message})"
        )
    return FieldProblemOut(field=field, rule=rule, message=f"{field}: {message}")


def _json(
    status: int, detail: str, problems: list[FieldProblemOut], headers: dict[str, str] | None = None
) -> JSONResponse:
    body = ErrorOut(detail=detail, errors=problems).model_dump()
    return JSONResponse(body, status_code=status, headers=headers)


async def on_validation_error(_request: Request, exc: Exception) -> JSONResponse:
    """422 naming each refused field; 400 when the body is not JSON at all."""
    assert isinstance(exc, RequestValidationError)
    problems = [_problem(dict(e), exc.body) for e in exc.errors()]
    status = 400 if any(p.rule == "json_invalid" for p in problems) else 422
    return _json(status, "; ".join(p.message for p in problems) or "invalid request", problems)


async def on_service_error(_request: Request, exc: Exception) -> JSONResponse:
    """A domain refusal with its own status (and its headers, such as a 429's Retry-After)."""
    assert isinstance(exc, ServiceError)
    problems = [FieldProblemOut(field=p.field, rule=p.rule, message=p.message) for p in exc.problems]
    return _json(exc.status, exc.message, problems, headers=getattr(exc, "headers", None))


# Starlette's and FastAPI's own refusals carry no field; name the part of the request they refuse.
_HTTP_PROBLEMS: dict[int, tuple[str, str]] = {
    400: ("body", "json_invalid"),
    401: ("Authorization", "authentication"),
    404: ("path", "not_found"),
    405: ("method", "method_not_allowed"),
}
_PARSE_FAILURE = "There was an error parsing the body"
_HTTP_METHODS = {"GET", "PUT", "POST", "DELETE", "OPTIONS", "HEAD", "PATCH", "TRACE"}


def allowed_methods(request: Request) -> list[str]:
    """The methods the OpenAPI schema documents at this request's path.

    Starlette's own 405 names only the methods of the first route it tried, so a path served by
    two routes (GET and POST /api/v1/inspections) would answer with half of the truth.
    """
    methods: set[str] = set()
    for template, operations in request.app.openapi().get("paths", {}).items():
        if _template_pattern(template).fullmatch(request.url.path):
            methods.update(method.upper() for method in operations if method.upper() in _HTTP_METHODS)
    return sorted(methods)


@lru_cache(maxsize=256)
def _template_pattern(template: str) -> re.Pattern[str]:
    """/api/v1/vehicles/{registration_number} -> a pattern with one path segment per parameter."""
    parts = re.split(r"(\{[^}]+\})", template)
    return re.compile("".join("[^/]+" if part.startswith("{") else re.escape(part) for part in parts))


async def on_http_error(request: Request, exc: Exception) -> JSONResponse:
    """Starlette's HTTP errors (400 unparsable body, 401, 404 of unknown paths, 405) in the same shape."""
    assert isinstance(exc, StarletteHTTPException)
    headers = dict(getattr(exc, "headers", None) or {})
    detail = str(exc.detail)
    if exc.status_code == 400 and detail == _PARSE_FAILURE:
        detail = "body: the request body could not be read as UTF-8 JSON"
    elif exc.status_code == 405:
        starlette_allows = [m.strip() for m in headers.get("Allow", "").split(",") if m.strip()]
        methods = allowed_methods(request) or sorted(starlette_allows)
        if methods:
            headers["Allow"] = ", ".join(methods)
        detail = f"method: {request.method} is not allowed at this path; use {' or '.join(methods)}"
    elif exc.status_code == 404 and detail == "Not Found":
        detail = f"path: {request.url.path} does not exist; the station API lives under /api/v1"
    problems = []
    if exc.status_code in _HTTP_PROBLEMS:
        field, rule = _HTTP_PROBLEMS[exc.status_code]
        problems.append(FieldProblemOut(field=field, rule=rule, message=detail))
    return _json(exc.status_code, detail, problems, headers=headers or None)


def note_outage(request: Request, error: BaseException) -> None:
    """One warning line for a request the database could not serve: what failed, without a traceback.

    The driver's first line only: SQLAlchemy's text goes on to quote the statement and its values.
    """
    cause = getattr(error, "orig", None) or error
    reason = (str(cause).strip().splitlines() or [""])[0][:300]
    outage_log.warning(
        "database unavailable",
        extra={
            "fields": {
                "request_id": getattr(request.state, "request_id", None),
                "method": request.method,
                "path": request.url.path,
                "error": f"{type(cause).__name__}: {reason}",
            }
        },
    )


def retry_later_headers() -> dict[str, str]:
    """The headers of a 503 answered while the database is away."""
    return {"Retry-After": str(RETRY_AFTER_SECONDS)}


UNAVAILABLE_MESSAGE = (
    f"database: the database is not answering; try again in {RETRY_AFTER_SECONDS} seconds "
    "(a request sent again with the same Idempotency-Key is never stored twice)"
)


# Documented on every API operation: any of them may meet a database that is away.
UNAVAILABLE_RESPONSE: dict[int | str, dict[str, Any]] = {
    503: {
        "model": ErrorOut,
        "description": "The database is not answering; send the request again after Retry-After seconds.",
        "headers": {
            "Retry-After": {
                "description": "Seconds to wait before trying again.",
                "schema": {"type": "integer"},
            }
        },
    }
}


async def on_database_error(request: Request, exc: Exception) -> JSONResponse:
    """503 with Retry-After while the database is away; any other database error stays a 500."""
    if not is_outage(exc):
        raise exc
    note_outage(request, exc)
    problem = FieldProblemOut(field="database", rule="unavailable", message=UNAVAILABLE_MESSAGE)
    return _json(503, UNAVAILABLE_MESSAGE, [problem], headers=retry_later_headers())


def install_error_handlers(app: FastAPI) -> None:
    """Register the JSON error handlers on the app."""
    app.add_exception_handler(RequestValidationError, on_validation_error)
    app.add_exception_handler(ServiceError, on_service_error)
    app.add_exception_handler(StarletteHTTPException, on_http_error)
    for kind in DATABASE_ERRORS:
        app.add_exception_handler(kind, on_database_error)
