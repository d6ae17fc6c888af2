"""The yardsticks of the load benchmark, served by uvicorn beside trikecert on the same database.

`peer_app`: the endpoint a developer would write in an afternoon: FastAPI, a pydantic body, sync
SQLAlchemy ORM, one row inserted and committed (durable: PostgreSQL's default synchronous_commit=on,
SQLite in WAL with synchronous=FULL, as trikecert), no key check, no idempotency, no assessment.
`bare_app`: one Starlette route answering a fixed JSON body, the ceiling of an ASGI app on uvicorn.

    uvicorn --app-dir bench peer:peer_app --workers 2   (PEER_DATABASE_URL: the database to write to)
    uvicorn --app-dir bench peer:bare_app --workers 2
"""

from __future__ import annotations

import os
from datetime import UTC, datetime
from typing import Any

from fastapi import FastAPI
from pydantic import BaseModel
from sqlalchemy import JSON, DateTime, String, create_engine, event
from sqlalchemy.orm import DeclarativeBase, Mapped, Session, mapped_column, sessionmaker
from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse
from starlette.routing import Route


class Readings(BaseModel):
    front_kg: list[float]
    left_rear_kg: list[float]
    right_rear_kg: list[float]
    overall_kg: float | None = None


class SubmissionIn(BaseModel):
    registration_number: str
    readings: Readings


class Base(DeclarativeBase):
    pass


class PeerSubmission(Base):
    __tablename__ = "peer_submission"

    id: Mapped[int] = mapped_column(primary_key=True)
    registration_number: Mapped[str] = mapped_column(String(32))
    readings: Mapped[dict[str, Any]] = mapped_column(JSON)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))


def _engine() -> Any:
    url = os.environ["PEER_DATABASE_URL"]
    if not url.startswith("sqlite"):
        return create_engine(url, pool_size=16, max_overflow=16)
    engine = create_engine(url, connect_args={"check_same_thread": False, "timeout": 30})

    @event.listens_for(engine, "connect")
    def _durable(dbapi_connection: Any, _record: Any) -> None:
        dbapi_connection.execute("PRAGMA journal_mode=WAL")
        dbapi_connection.execute("PRAGMA synchronous=FULL")
        dbapi_connection.execute("PRAGMA busy_timeout=30000")

    return engine


peer_app = FastAPI()
_sessions: sessionmaker[Session] | None = None


def create_table(url: str) -> None:
    """Create the peer's table (once, before its workers start)."""
    engine = create_engine(url)
    Base.metadata.create_all(engine)
    engine.dispose()


@peer_app.on_event("startup")
def _connect() -> None:
    global _sessions
    _sessions = sessionmaker(_engine())


@peer_app.post("/api/v1/inspections", status_code=201)
def submit(body: SubmissionIn) -> dict[str, Any]:
    assert _sessions is not None
    with _sessions() as session:
        row = PeerSubmission(
            registration_number=body.registration_number,
            readings=body.readings.model_dump(),
            created_at=datetime.now(UTC),
        )
        session.add(row)
        session.commit()
        return {"id": row.id, "registration_number": row.registration_number}


async def _ok(_request: Request) -> JSONResponse:
    return JSONResponse({"status": "ok"})


bare_app = Starlette(routes=[Route("/healthz", _ok)])
