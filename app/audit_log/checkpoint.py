"""Signed checkpoints of the audit chain: after a full check, the head's id and hash signed with the
signing key, which is held outside the database (JWS compact, Ed25519), stored, and published for
regulators and anyone else to keep.

A published checkpoint holds the service to its past: an event edited, removed or inserted at or
before it no longer matches it, even when every SHA-256 link after the edit was computed again (the
chain alone needs no secret to rewrite; the checkpoint's signature does), and removing the newest
events shows too, since the checkpoint names an event that is gone. `trikecert audit-verify` checks
every stored checkpoint against the chain and signs nothing over a chain that contradicts one. Each
checkpoint names the SHA-256 of the checkpoint token before it (`previous`), so the published history
is a chain of its own: a copy kept outside proves a later rewrite even if the stored checkpoints are
replaced. The audit page checks the newest checkpoint and only the events after it, so its cost does
not grow with the log.
"""

from __future__ import annotations

import base64
import binascii
import hashlib
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
from app.config import Settings
from app.db import begin_write, utcnow
from app.errors import Conflict
from app.i18n.active import gettext as _
from app.trust.claims import find_key
from app.trust.keys import current_signer, published_keys
from app.trust.signer import Signer

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


def _b64(raw: bytes) -> str:
    return base64.urlsafe_b64encode(raw).rstrip(b"=").decode()


def token_digest(token: str) -> str:
    """SHA-256 of a checkpoint's token, hex: what the next checkpoint names as `previous`."""
    return hashlib.sha256(token.encode()).hexdigest()


def sign_claims(signer: Signer, claims: dict[str, Any]) -> str:
    """A JWS compact of the claims, Ed25519 by the signer (which may be a token that never lets the
    private key out)."""
    header = _b64(json.dumps({"alg": ALGORITHM, "kid": signer.kid}, separators=(",", ":")).encode())
    payload = _b64(json.dumps(claims, separators=(",", ":"), sort_keys=True).encode())
    return f"{header}.{payload}.{_b64(signer.sign(f'{header}.{payload}'.encode()))}"


def all_checkpoints(session: Session) -> list[AuditCheckpoint]:
    """Every stored checkpoint, oldest first."""
    return list(session.scalars(select(AuditCheckpoint).order_by(AuditCheckpoint.id)))


def contradiction(session: Session, settings: Settings) -> tuple[AuditCheckpoint, str] | None:
    """The first stored checkpoint (oldest first) that the chain as stored contradicts, and why: a
    signature no published key made, a claim that differs from the row, a broken `previous` link, an
    event gone, or an event whose stored hash is not the one signed."""
    jwks = published_keys(session, settings)
    previous: AuditCheckpoint | None = None
    for checkpoint in all_checkpoints(session):
        problem = _checkpoint_problem(session, checkpoint, jwks, previous)
        if problem is not None:
            return checkpoint, problem
        previous = checkpoint
    return None


def verify_all(session: Session, settings: Settings) -> ChainReport:
    """Check every event from the first, then every stored checkpoint against the chain."""
    report = verify_chain(_events(session))
    if not report.intact:
        return report
    found = contradiction(session, settings)
    if found is None:
        return report
    checkpoint, problem = found
    if checkpoint.event_id > report.events:
        missing = report.events + 1
        signed = _("checkpoint %(checkpoint)s was signed at event %(event)s") % {
            "checkpoint": checkpoint.id,
            "event": checkpoint.event_id,
        }
        reason = _("event %(missing)s is missing: %(signed)s") % {"missing": missing, "signed": signed}
        return ChainReport(report.events, missing, reason)
    # What the last checkpoint that holds signed is proven; the change lies after it, up to this one.
    proven = session.scalar(
        select(AuditCheckpoint.event_id)
        .where(AuditCheckpoint.id < checkpoint.id)
        .order_by(AuditCheckpoint.id.desc())
        .limit(1)
    )
    return ChainReport(proven or 0, checkpoint.event_id, problem)


class ChainContradicted(Conflict):
    """A new checkpoint was asked for over a chain that an earlier checkpoint contradicts."""


def _refuse(reason: str) -> ChainContradicted:
    message = _("no checkpoint signed: %(reason)s") % {"reason": reason}
    return ChainContradicted(message, field="audit", rule="checkpoint_contradicted")


def record_checkpoint(session: Session, settings: Settings, *, event_id: int) -> AuditCheckpoint:
    """Sign and store a checkpoint at `event_id`, the last event a full check found intact; refused
    when any stored checkpoint contradicts the chain."""
    found = contradiction(session, settings)
    if found is not None:
        raise _refuse(found[1])
    signer = current_signer(session, settings)
    begin_write(session)
    head = session.get(AuditEvent, event_id)
    if head is None:
        raise ValueError(f"no audit event {event_id} to sign")
    newest = newest_checkpoint(session)
    if newest is not None and newest.event_id > head.id:
        later = _("checkpoint %(checkpoint)s was signed at a later event (%(event)s)")
        raise _refuse(later % {"checkpoint": newest.id, "event": newest.event_id})
    now = utcnow()
    claims = {
        "chain": "trikecert-audit",
        "event": head.id,
        "hash": head.hash,
        "at": now.isoformat(),
        "previous": token_digest(newest.token) if newest is not None else None,
    }
    checkpoint = AuditCheckpoint(
        event_id=head.id, hash=head.hash, created_at=now, kid=signer.kid, token=sign_claims(signer, claims)
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


def _checkpoint_problem(
    session: Session,
    checkpoint: AuditCheckpoint,
    jwks: dict[str, Any],
    previous: AuditCheckpoint | None = None,
) -> str | None:
    claims = checkpoint_claims(checkpoint.token, jwks)
    if claims is None or claims.get("event") != checkpoint.event_id or claims.get("hash") != checkpoint.hash:
        return _("checkpoint %(checkpoint)s is not as a published key signed it") % {
            "checkpoint": checkpoint.id
        }
    # Checkpoints signed before `previous` was a claim carry none; every later one names the last.
    if previous is not None and "previous" in claims and claims["previous"] != token_digest(previous.token):
        unlinked = _("checkpoint %(checkpoint)s does not follow checkpoint %(previous)s as it was signed")
        return unlinked % {"checkpoint": checkpoint.id, "previous": previous.id}
    event = session.get(AuditEvent, checkpoint.event_id)
    if event is None:
        missing = _("event %(event)s is missing: checkpoint %(checkpoint)s was signed at it")
        return missing % {"event": checkpoint.event_id, "checkpoint": checkpoint.id}
    if event_hash(_fields(event)) != event.hash:
        changed = _("event %(event)s was changed after checkpoint %(checkpoint)s was signed")
        return changed % {"event": checkpoint.event_id, "checkpoint": checkpoint.id}
    if event.hash != checkpoint.hash:
        signed = checkpoint.created_at.strftime("%Y-%m-%d %H:%M UTC")
        rewritten = _(
            "the chain up to event %(event)s was rewritten after checkpoint %(checkpoint)s was signed "
            "(%(signed)s): the checkpoint signed hash %(signed_hash)s…, the event now holds %(held_hash)s…"
        )
        return rewritten % {
            "event": checkpoint.event_id,
            "checkpoint": checkpoint.id,
            "signed": signed,
            "signed_hash": checkpoint.hash[:16],
            "held_hash": event.hash[:16],
        }
    return None


def verify_since_checkpoint(session: Session, settings: Settings) -> PageCheck:
    """The newest checkpoint (its signature, and the event it names) and every event after it; the
    whole chain when there is no checkpoint yet."""
    checkpoint = newest_checkpoint(session)
    if checkpoint is None:
        return PageCheck(verify_chain(_events(session)), None)
    problem = _checkpoint_problem(session, checkpoint, published_keys(session, settings))
    if problem is not None:
        return PageCheck(ChainReport(0, checkpoint.event_id, problem), checkpoint)
    rest = verify_chain(
        _events(session, after=checkpoint.event_id), after_id=checkpoint.event_id, after_hash=checkpoint.hash
    )
    return PageCheck(ChainReport(checkpoint.event_id + rest.events, rest.broken_at, rest.reason), checkpoint)
