"""/healthz (the process answers) and /readyz (database reachable and migrations at head)."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import JSONResponse, Response
from sqlalchemy import text
from sqlalchemy.exc import SQLAlchemyError

from app.db import get_engine
from app.migrate import is_at_head

router = APIRouter(tags=["operations"])


HEALTHY_BODY = b'{"status":"ok"}'


@router.get("/healthz", include_in_schema=False)
async def healthz() -> Response:
    """Answers as long as the process serves requests; touches nothing else.

    A GET never gets here: `LivenessFirst` (app/ops/liveness.py) answers it the same way, ahead of
    the framework. The route stays as the answer's definition, and for the 405 of other methods.
    """
    return Response(HEALTHY_BODY, media_type="application/json")


@router.get("/readyz", include_in_schema=False)
def readyz() -> JSONResponse:
    """200 when the database answers and carries the newest migration, else 503 with the reason."""
    engine = get_engine()
    try:
        with engine.connect() as connection:
            connection.execute(text("SELECT 1"))
        at_head = is_at_head(engine)
    except SQLAlchemyError as error:
        return JSONResponse({"status": "unavailable", "reason": f"database: {type(error).__name__}"}, 503)
    if not at_head:
        return JSONResponse({"status": "unavailable", "reason": "migrations: run `trikecert migrate`"}, 503)
    return JSONResponse({"status": "ok"})
