"""The audit log's hash chain, pure: any edit, removal, insertion or reordering is found."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from dataclasses import replace
from datetime import UTC, datetime, timedelta

import pytest

from app.audit.chain import GENESIS, EventFields, event_hash, verify_chain

Events = list[tuple[EventFields, str]]
START = datetime(2026, 12, 1, 9, 30, tzinfo=UTC)


def independent_hash(fields: EventFields) -> str:
    """The documented hash, written out again: SHA-256 of the previous hash, a newline, and the JSON
    list of the event's fields with its time in UTC to the microsecond."""
    body = [
        fields.id,
        fields.occurred_at.astimezone(UTC).strftime("%Y-%m-%dT%H:%M:%S.%fZ"),
        fields.actor_kind,
        fields.actor_id,
        fields.actor_label,
        fields.action,
        fields.target_type,
        fields.target_id,
        fields.details,
    ]
    if fields.client_address is not None or fields.request_id is not None:
        body += [fields.client_address, fields.request_id]
    text = json.dumps(body, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(f"{fields.previous_hash}\n{text}".encode()).hexdigest()


def chain(length: int) -> Events:
    events, previous = [], GENESIS
    for n in range(1, length + 1):
        fields = EventFields(
            id=n,
            occurred_at=START + timedelta(minutes=n),
            actor_kind="user",
            actor_id=7,
            actor_label="admin@example.org",
            action="station.created",
            target_type="station",
            target_id=str(n),
            details=json.dumps({"name": f"Ṣàngó weighbridge {n}"}, ensure_ascii=False),
            previous_hash=previous,
        )
        previous = independent_hash(fields)
        events.append((fields, previous))
    return events


def test_the_hash_is_the_documented_one() -> None:
    fields, stored = chain(1)[0]
    assert event_hash(fields) == stored


def test_an_event_without_a_request_origin_hashes_as_events_did_before_origins_were_kept() -> None:
    fields, _stored = chain(1)[0]
    # Computed by the code of the release before origins were kept: stored events must still verify.
    assert event_hash(fields) == "4090b91822b972a01cb44da338809ddd4724175b92b544b47068a5774fcfaace"


@pytest.mark.parametrize(
    ("client_address", "request_id"), [("203.0.113.7", None), (None, "3f2a9c"), ("2001:db8::1", "3f2a9c")]
)
def test_the_request_origin_is_covered_by_the_hash(
    client_address: str | None, request_id: str | None
) -> None:
    fields = replace(chain(1)[0][0], client_address=client_address, request_id=request_id)
    stored = event_hash(fields)
    assert stored == independent_hash(fields)
    assert stored != event_hash(replace(fields, client_address="198.51.100.9"))
    assert stored != event_hash(replace(fields, request_id="forged"))


def test_an_untouched_chain_is_intact() -> None:
    report = verify_chain(chain(5))
    assert report.intact
    assert report.events == 5


def _edit(events: Events) -> Events:
    fields, stored = events[2]
    return [*events[:2], (replace(fields, details='{"name":"someone else"}'), stored), *events[3:]]


def _remove(events: Events) -> Events:
    return events[:2] + events[3:]


def _swap(events: Events) -> Events:
    return [events[0], events[2], events[1], *events[3:]]


def _rehash_one(events: Events) -> Events:
    fields, _stored = events[2]
    edited = replace(fields, actor_label="somebody innocent")
    return [*events[:2], (edited, independent_hash(edited)), *events[3:]]


@pytest.mark.parametrize(
    ("tamper", "broken_at", "reason"),
    [
        (_edit, 3, "event 3 was changed after it was recorded"),
        (_remove, 4, "event 3 is missing: the next on record is 4"),
        (_swap, 3, "event 2 is missing: the next on record is 3"),
        (_rehash_one, 4, "event 4 does not follow event 3"),
    ],
)
def test_tampering_is_found_at_the_first_event_it_touched(
    tamper: Callable[[Events], Events], broken_at: int, reason: str
) -> None:
    report = verify_chain(tamper(chain(5)))
    assert not report.intact
    assert report.broken_at == broken_at
    assert report.reason == reason
