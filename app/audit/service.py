"""Reading the audit log back: a page of events, and the check of the whole chain."""

from __future__ import annotations

from collections.abc import Sequence

from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.audit.chain import ChainReport
from app.audit.checkpoint import verify_all
from app.audit.models import AuditEvent


def list_events(session: Session, *, page: int, page_size: int) -> tuple[Sequence[AuditEvent], int]:
    """A page of events, newest first, and how many there are in all."""
    total = int(session.scalar(select(func.count()).select_from(AuditEvent)) or 0)
    query = select(AuditEvent).order_by(AuditEvent.id.desc()).offset((page - 1) * page_size).limit(page_size)
    return session.scalars(query).all(), total


def verify_log(session: Session) -> ChainReport:
    """Check every event of the log against its hash and its place in the chain, from the first."""
    return verify_all(session)
