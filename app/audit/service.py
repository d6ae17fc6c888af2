"""Reading the audit log back: a page of events, and the check of the whole chain."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.audit.chain import ChainReport, EventFields, verify_chain
from app.audit.models import AuditEvent

FIELDS = tuple(EventFields.__dataclass_fields__)


def list_events(session: Session, *, page: int, page_size: int) -> tuple[Sequence[AuditEvent], int]:
    """A page of events, newest first, and how many there are in all."""
    total = int(session.scalar(select(func.count()).select_from(AuditEvent)) or 0)
    query = select(AuditEvent).order_by(AuditEvent.id.desc()).offset((page - 1) * page_size).limit(page_size)
    return session.scalars(query).all(), total


def _stored(session: Session) -> Iterator[tuple[EventFields, str]]:
    rows = session.execute(select(AuditEvent).order_by(AuditEvent.id).execution_options(yield_per=1000))
    for (event,) in rows:
        yield EventFields(**{name: getattr(event, name) for name in FIELDS}), event.hash


def verify_log(session: Session) -> ChainReport:
    """Check every event of the log against its hash and its place in the chain."""
    return verify_chain(_stored(session))
