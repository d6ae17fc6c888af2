"""Signed checkpoints of the audit chain: after a full check, the head's id and hash signed with the
certificate signing key (JWS compact, Ed25519), stored, and published for regulators to keep.

A published checkpoint holds the service to its past: an event edited, removed or inserted at or
before it no longer matches it, and removing the newest events (which leaves a chain that checks)
shows too, since the checkpoint names an event that is gone. The audit page checks the newest
checkpoint and only the events after it, so its cost does not grow with the log.
"""

from __future__ import annotations

import base64
import binascii
import json
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from joserfc import jws
from joserfc.errors import JoseError
from joserfc.jwk import OKPKey
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.audit.chain import ChainReport, EventFields, event_hash, verify_chain
from app.audit.models import AuditCheckpoint, AuditEvent
from app.certificates.claims import find_key
from app.certificates.keys import current_signer, published_keys
from app.config import Settings
from app.db import begin_write, utcnow

ALGORITHM = "Ed25519"
FIELDS = tuple(EventFields.__dataclass_fields__)


@dataclass(frozen=True)
class PageCheck:
    """What a check found, and the checkpoint it started from (None: it checked from the first event)."""

    report: ChainReport
    checkpoint: AuditCheckpoint | None


def _fields(event: AuditEvent) -> EventFields:
    return EventFields(**{name: getattr(event, name) for name in FIELDS})


def _events(session: Session, after: int = 0) -> Iterator[tuple[EventFields, str]]:
    query = select(AuditEvent).where(AuditEvent.id > after).order_by(AuditEvent.id)
    for (event,) in session.execute(query.execution_options(yield_per=1000)):
        yield _fields(event), event.hash


def newest_checkpoint(session: Session) -> AuditCheckpoint | None:
    """The last checkpoint signed, if any."""
    query = select(AuditCheckpoint).order_by(AuditCheckpoint.id.desc()).limit(1)
    return session.scalars(query).first()


def verify_all(session: Session) -> ChainReport:
    """Check every event from the first, and that the newest checkpoint's event is still there."""
    report = verify_chain(_events(session))
    newest = newest_checkpoint(session)
    if report.intact and newest is not None and newest.event_id > report.events:
        missing = report.events + 1
        reason = f"event {missing} is missing: checkpoint {newest.id} was signed at event {newest.event_id}"
        return ChainReport(report.events, missing, reason)
    return report


def record_checkpoint(session: Session, settings: Settings, *, event_id: int) -> AuditCheckpoint:
    """Sign and store a checkpoint at `event_id`, the last event a full check found intact."""
    signer = current_signer(session, settings)
    begin_write(session)
    head = session.get(AuditEvent, event_id)
    if head is None:
        raise ValueError(f"no audit event {event_id} to sign")
    now = utcnow()
    claims = {"chain": "trikecert-audit", "event": head.id, "hash": head.hash, "at": now.isoformat()}
    token = jws.serialize_compact(
        {"alg": ALGORITHM, "kid": signer.kid},
        json.dumps(claims, separators=(",", ":"), sort_keys=True).encode(),
        signer.key,
        algorithms=[ALGORITHM],
    )
    checkpoint = AuditCheckpoint(
        event_id=head.id, hash=head.hash, created_at=now, kid=signer.kid, token=token
    )
    session.add(checkpoint)
    session.commit()
    return checkpoint


def _kid(token: str) -> str | None:
    first = token.split(".", 1)[0]
    try:
        header = json.loads(base64.urlsafe_b64decode(first + "=" * (-len(first) % 4)))
    except (binascii.Error, ValueError):
        return None
    kid = header.get("kid") if isinstance(header, dict) else None
    return kid if isinstance(kid, str) else None


def checkpoint_claims(token: str, jwks: dict[str, Any]) -> dict[str, Any] | None:
    """The claims of a checkpoint token when a published key signed it, else None."""
    kid = _kid(token)
    public = find_key(jwks, kid) if kid is not None else None
    if public is None:
        return None
    try:
        key = OKPKey.import_key({name: public[name] for name in ("kty", "crv", "x")})
        claims = json.loads(jws.deserialize_compact(token, key, algorithms=[ALGORITHM]).payload)
    except (JoseError, KeyError, ValueError, TypeError):
        return None
    return claims if isinstance(claims, dict) else None


def _checkpoint_problem(session: Session, checkpoint: AuditCheckpoint, settings: Settings) -> str | None:
    claims = checkpoint_claims(checkpoint.token, published_keys(session, settings))
    if claims is None or claims.get("event") != checkpoint.event_id or claims.get("hash") != checkpoint.hash:
        return f"checkpoint {checkpoint.id} is not as a published key signed it"
    event = session.get(AuditEvent, checkpoint.event_id)
    if event is None:
        return f"event {checkpoint.event_id} is missing: checkpoint {checkpoint.id} was signed at it"
    if event.hash != checkpoint.hash or event_hash(_fields(event)) != event.hash:
        return f"event {checkpoint.event_id} was changed after checkpoint {checkpoint.id} was signed"
    return None


def verify_since_checkpoint(session: Session, settings: Settings) -> PageCheck:
    """The newest checkpoint (its signature, and the event it names) and every event after it; the
    whole chain when there is no checkpoint yet."""
    checkpoint = newest_checkpoint(session)
    if checkpoint is None:
        return PageCheck(verify_chain(_events(session)), None)
    problem = _checkpoint_problem(session, checkpoint, settings)
    if problem is not None:
        return PageCheck(ChainReport(0, checkpoint.event_id, problem), checkpoint)
    rest = verify_chain(
        _events(session, after=checkpoint.event_id), after_id=checkpoint.event_id, after_hash=checkpoint.hash
    )
    return PageCheck(ChainReport(checkpoint.event_id + rest.events, rest.broken_at, rest.reason), checkpoint)
