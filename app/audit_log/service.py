"""Reading the audit log back: the events a filter picks, a page or all of them, and the check of the
whole chain."""

from __future__ import annotations

import unicodedata
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from datetime import datetime

from sqlalchemy import ColumnElement, Select, func, or_, select
from sqlalchemy.orm import Session

from app.audit.chain import ChainReport
from app.audit.models import AuditEvent
from app.audit_log.checkpoint import verify_all
from app.config import Settings, get_settings

ACTOR_KINDS = ("user", "station", "command_line", "anonymous")


@dataclass(frozen=True)
class AuditFilter:
    """Which events to show; an empty field does not narrow. `action` ending in "." is a prefix."""

    actor: str = ""  # part of the actor's label, any case
    actor_kind: str = ""
    action: str = ""
    target_type: str = ""
    target_id: str = ""
    since: datetime | None = None  # inclusive
    until: datetime | None = None  # exclusive


def _folded(text: str) -> str:
    return unicodedata.normalize("NFC", text).casefold()


def _actor_labels(session: Session, part: str) -> list[str]:
    # Matched here rather than by the database's LOWER/ILIKE, which fold only ASCII on SQLite (and
    # under PostgreSQL's C collation): "ọ̀yọ́" must find "Ọ̀yọ́ weighbridge" on both. Actors are few.
    wanted = _folded(part)
    labels = session.scalars(select(AuditEvent.actor_label).distinct())
    return [label for label in labels if wanted in _folded(label)]


def _conditions(session: Session, where: AuditFilter) -> list[ColumnElement[bool]]:
    found: list[ColumnElement[bool]] = []
    if where.actor:
        found.append(AuditEvent.actor_label.in_(_actor_labels(session, where.actor)))
    if where.actor_kind:
        found.append(AuditEvent.actor_kind == where.actor_kind)
    if where.action.endswith("."):
        # "sign_in." picks every sign-in action; "sign_out." the one action of that kind, "sign_out".
        found.append(
            or_(
                AuditEvent.action.startswith(where.action, autoescape=True),
                AuditEvent.action == where.action[:-1],
            )
        )
    elif where.action:
        found.append(AuditEvent.action == where.action)
    if where.target_type:
        found.append(AuditEvent.target_type == where.target_type)
    if where.target_id:
        found.append(AuditEvent.target_id == where.target_id)
    if where.since is not None:
        found.append(AuditEvent.occurred_at >= where.since)
    if where.until is not None:
        found.append(AuditEvent.occurred_at < where.until)
    return found


def _newest_first(conditions: list[ColumnElement[bool]]) -> Select[AuditEvent]:
    return select(AuditEvent).where(*conditions).order_by(AuditEvent.id.desc())


def list_events(
    session: Session, *, page: int, page_size: int, where: AuditFilter | None = None
) -> tuple[Sequence[AuditEvent], int]:
    """A page of the events the filter picks, newest first, and how many it picks in all."""
    conditions = _conditions(session, where or AuditFilter())
    total = int(session.scalar(select(func.count()).select_from(AuditEvent).where(*conditions)) or 0)
    query = _newest_first(conditions).offset((page - 1) * page_size).limit(page_size)
    return session.scalars(query).all(), total


def all_events(session: Session, where: AuditFilter) -> Iterator[AuditEvent]:
    """Every event the filter picks, newest first, read a thousand at a time."""
    query = _newest_first(_conditions(session, where)).execution_options(yield_per=1000)
    yield from session.scalars(query)


def actions_on_record(session: Session) -> list[str]:
    """Every action the log holds, in alphabetical order."""
    return list(session.scalars(select(AuditEvent.action).distinct().order_by(AuditEvent.action)))


def record_types_on_record(session: Session) -> list[str]:
    """Every kind of record the log names, in alphabetical order."""
    return list(session.scalars(select(AuditEvent.target_type).distinct().order_by(AuditEvent.target_type)))


def verify_log(session: Session, settings: Settings | None = None) -> ChainReport:
    """Check every event of the log against its hash and its place in the chain, from the first, and
    every stored checkpoint against the chain."""
    return verify_all(session, settings or get_settings())
