"""The hash chain: how an event's hash is computed, and the check that no event was edited, removed or
inserted. Pure: no database."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

from app.i18n.active import gettext as _

GENESIS = "0" * 64


@dataclass(frozen=True)
class EventFields:
    """The fields of an event that its hash covers (all of them but the hash)."""

    id: int
    occurred_at: datetime
    actor_kind: str
    actor_id: int | None
    actor_label: str
    action: str
    target_type: str
    target_id: str | None
    details: str
    previous_hash: str
    client_address: str | None = None
    request_id: str | None = None


def canonical_json(value: Any) -> str:
    """JSON with sorted keys and no spaces, so that the same facts always hash the same."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, default=str)


def event_hash(fields: EventFields) -> str:
    """SHA-256 of the previous hash and the event's fields, hex."""
    moment = fields.occurred_at.astimezone(UTC).strftime("%Y-%m-%dT%H:%M:%S.%fZ")
    covered: list[Any] = [
        fields.id,
        moment,
        fields.actor_kind,
        fields.actor_id,
        fields.actor_label,
        fields.action,
        fields.target_type,
        fields.target_id,
        fields.details,
    ]
    # Events from before the request's origin was recorded have neither, and hash as they always did.
    if fields.client_address is not None or fields.request_id is not None:
        covered += [fields.client_address, fields.request_id]
    body = canonical_json(covered)
    return hashlib.sha256(f"{fields.previous_hash}\n{body}".encode()).hexdigest()


@dataclass(frozen=True)
class ChainReport:
    """The outcome of checking the chain: how many events were checked, and the first that is wrong."""

    events: int
    broken_at: int | None = None
    reason: str = ""

    @property
    def intact(self) -> bool:
        """True when every event is where it was written, unedited."""
        return self.broken_at is None


def verify_chain(
    events: Iterable[tuple[EventFields, str]], *, after_id: int = 0, after_hash: str = GENESIS
) -> ChainReport:
    """Check events in id order, each with its stored hash: ids without gaps from `after_id + 1`, each
    linked to the one before (the first to `after_hash`), each hash matching its fields."""
    previous, expected_id, count = after_hash, after_id + 1, 0
    for fields, stored_hash in events:
        if fields.id != expected_id:
            missing = _("event %(missing)s is missing: the next on record is %(found)s")
            return ChainReport(count, fields.id, missing % {"missing": expected_id, "found": fields.id})
        if fields.previous_hash != previous:
            unlinked = _("event %(event)s does not follow event %(before)s")
            return ChainReport(count, fields.id, unlinked % {"event": fields.id, "before": fields.id - 1})
        if event_hash(fields) != stored_hash:
            changed = _("event %(event)s was changed after it was recorded")
            return ChainReport(count, fields.id, changed % {"event": fields.id})
        previous, expected_id, count = stored_hash, expected_id + 1, count + 1
    return ChainReport(count)
