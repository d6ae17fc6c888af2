"""Every refusal as JSON `{detail, errors: [{field, rule, message}]}`; never a bare 500 for bad input."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel
from starlette.exceptions import HTTPException as StarletteHTTPException

from app.errors import ServiceError


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


def field_path(loc: Sequence[int | str]) -> str:
    """('body', 'readings', 'front_kg', 0) -> 'readings.front_kg[0]'."""
    parts = list(loc[1:]) if loc and loc[0] in ("body", "query", "path", "header") else list(loc)
    path = ""
    for part in parts:
        if isinstance(part, int):
            path += f"[{part}]"
        else:
            path += f".{part}" if path else str(part)
    return path or (str(loc[0]) if loc else "body")


def _problem(error: dict[str, Any]) -> FieldProblemOut:
    field = field_path(error.get("loc", ()))
    message = str(error.get("msg", "invalid value"))
    if message.startswith("Value error, "):
        message = message.removeprefix("Value error, ")
    rule = str(error.get("type", "invalid"))
    if rule == "json_invalid":
        return FieldProblemOut(field="body", rule=rule, message=f"body: the request is not valid JSON ({message})")
    return FieldProblemOut(field=field, rule=rule, message=f"{field}: {message}")


def _json(status: int, detail: str, problems: list[FieldProblemOut], headers: dict[str, str] | None = None) -> JSONResponse:
    body = ErrorOut(detail=detail, errors=problems).model_dump()
    return JSONResponse(body, status_code=status, headers=headers)


async def on_validation_error(_request: Request, exc: Exception) -> JSONResponse:
    """422 naming each refused field; 400 when the body is not JSON at all."""
    assert isinstance(exc, RequestValidationError)
    problems = [_problem(dict(e)) for e in exc.errors()]
    status = 400 if any(p.rule == "json_invalid" for p in problems) else 422
    return _json(status, "; ".join(p.message for p in problems) or "invalid request", problems)


async def on_service_error(_request: Request, exc: Exception) -> JSONResponse:
    """A domain refusal with its own status."""
    assert isinstance(exc, ServiceError)
    problems = [FieldProblemOut(field=p.field, rule=p.rule, message=p.message) for p in exc.problems]
    return _json(exc.status, exc.message, problems)


async def on_http_error(_request: Request, exc: Exception) -> JSONResponse:
    """Starlette's HTTP errors (401, 404 of unknown paths, 405) in the same shape."""
    assert isinstance(exc, StarletteHTTPException)
    return _json(exc.status_code, str(exc.detail), [], headers=getattr(exc, "headers", None))


def install_error_handlers(app: FastAPI) -> None:
    """Register the JSON error handlers on the app."""
    app.add_exception_handler(RequestValidationError, on_validation_error)
    app.add_exception_handler(ServiceError, on_service_error)
    app.add_exception_handler(StarletteHTTPException, on_http_error)
