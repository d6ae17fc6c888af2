"""The audit log's published checkpoints: the newest (the head) and every one before it, for regulators
and anyone else to keep and compare."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated

from fastapi import APIRouter, Query, Response
from pydantic import BaseModel, ConfigDict, Field
from sqlalchemy import select

from app.api.errors import error_responses
from app.audit.models import AuditCheckpoint
from app.audit_log.checkpoint import newest_checkpoint
from app.errors import NotFound
from app.web.deps import SessionDep

router = APIRouter(tags=["audit"])


class AuditHead(BaseModel):
    """A signed statement that the audit chain was whole up to `event_id`, whose hash was `hash`."""

    model_config = ConfigDict(
        json_schema_extra={
            "examples": [
                {
                    "checkpoint": 3,
                    "event_id": 1520,
                    "hash": "4090b91822b972a01cb44da338809ddd4724175b92b544b47068a5774fcfaace",
                    "signed_at": "2026-12-01T23:30:00+00:00",
                    "kid": "pnGtlMm-TqGbkOP9",
                    "token": "eyJhbGciOiJFZDI1NTE5Iiwia2lkIjoicG5HdGxNbS1UcUdia09QOSJ9.eyJ...",
                }
            ]
        }
    )

    checkpoint: int
    event_id: int
    hash: str = Field(description="SHA-256 of the event, hex, as the chain holds it")
    signed_at: datetime
    kid: str = Field(description="The key in /.well-known/trikecert-keys.json that signed `token`")
    token: str = Field(
        description="JWS compact (Ed25519) of {chain, event, hash, at, previous}; `previous` is the "
        "SHA-256 (hex) of the token of the checkpoint before it"
    )

    @classmethod
    def of(cls, checkpoint: AuditCheckpoint) -> AuditHead:
        """The published form of a stored checkpoint."""
        return cls(
            checkpoint=checkpoint.id,
            event_id=checkpoint.event_id,
            hash=checkpoint.hash,
            signed_at=checkpoint.created_at,
            kid=checkpoint.kid,
            token=checkpoint.token,
        )


class AuditCheckpoints(BaseModel):
    """Signed checkpoints, oldest first: each token names the one before it, so the list is a chain."""

    checkpoints: list[AuditHead]
    more: bool = Field(description="True when more checkpoints follow; ask again with `after`")


PAGE = 500


@router.get(
    "/audit/head",
    summary="The newest signed checkpoint of the audit log (public)",
    responses={404: {"description": "No checkpoint has been signed yet"}},
)
def audit_head(session: SessionDep, response: Response) -> AuditHead:
    """Keep a copy: a later head must extend this one, and the service cannot deny having signed it."""
    checkpoint = newest_checkpoint(session)
    if checkpoint is None:
        raise NotFound("audit: no checkpoint has been signed yet", field="audit", rule="not_found")
    response.headers["Cache-Control"] = "public, max-age=60"
    return AuditHead.of(checkpoint)


@router.get(
    "/audit/checkpoints",
    summary="Every signed checkpoint of the audit log, oldest first (public)",
    responses=error_responses(422),
)
def audit_checkpoints(
    session: SessionDep,
    response: Response,
    after: Annotated[int, Query(ge=0, le=2**31 - 1, description="Only checkpoints after this one")] = 0,
) -> AuditCheckpoints:
    """Compare with the copies you kept: a checkpoint you hold that is missing or different here, or a
    token whose `previous` does not name the one before it, proves the log was rewritten."""
    query = select(AuditCheckpoint).where(AuditCheckpoint.id > after).order_by(AuditCheckpoint.id)
    rows = session.scalars(query.limit(PAGE + 1)).all()
    response.headers["Cache-Control"] = "public, max-age=60"
    return AuditCheckpoints(checkpoints=[AuditHead.of(row) for row in rows[:PAGE]], more=len(rows) > PAGE)
