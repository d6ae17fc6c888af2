"""An audit chain no insider can rewrite silently: the owner of the tables edits an event and computes
every SHA-256 link again to the head (no secret needed for that), and `trikecert audit-verify` still
fails, at the first signed checkpoint the rewrite crosses, and signs nothing over it; the published
checkpoints let anyone holding an old one prove the rewrite."""

from __future__ import annotations

import base64
import hashlib
import json
from dataclasses import replace
from typing import Any

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey
from fastapi.testclient import TestClient
from sqlalchemy import Engine, func, select, text
from sqlalchemy.orm import Session

from app.audit.chain import GENESIS, event_hash, verify_chain
from app.audit.models import AuditCheckpoint, AuditEvent
from app.audit_log.checkpoint import ChainContradicted, _events, _fields, record_checkpoint
from app.certificates.guard import immutability_lifted
from app.cli import main
from app.config import get_settings
from app.stations.service import create_station


def audit_verify(capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """`trikecert audit-verify`: its exit code and what it printed."""
    code = main(["audit-verify"])
    return code, capsys.readouterr().out


def stations(session: Session, *names: str) -> None:
    for name in names:
        create_station(session, name=name)


def rewrite_from(owner_engine: Engine, event_id: int, details: str) -> None:
    """As the tables' owner: change one event's details and recompute every hash from it to the head."""
    with Session(owner_engine) as reader:
        events = reader.scalars(select(AuditEvent).where(AuditEvent.id >= event_id).order_by(AuditEvent.id))
        previous = reader.scalar(select(AuditEvent.hash).where(AuditEvent.id == event_id - 1)) or GENESIS
        rows = []
        for event in events:
            fields = _fields(event)
            fields = replace(fields, details=details if event.id == event_id else fields.details)
            fields = replace(fields, previous_hash=previous)
            previous = event_hash(fields)
            rows.append({"id": event.id, "d": fields.details, "p": fields.previous_hash, "h": previous})
    with owner_engine.begin() as connection, immutability_lifted(connection):
        for row in rows:
            connection.execute(
                text("UPDATE audit_event SET details = :d, previous_hash = :p, hash = :h WHERE id = :id"), row
            )


def checkpoint_count(session: Session) -> int:
    session.expire_all()
    return int(session.scalar(select(func.count()).select_from(AuditCheckpoint)) or 0)


def test_a_rewritten_chain_fails_at_the_first_checkpoint_it_crosses_and_is_never_signed(
    session: Session, owner_engine: Engine, capsys: pytest.CaptureFixture[str], admin_web: TestClient
) -> None:
    stations(session, "Agbara weighbridge", "Ikeja weighbridge", "Ọ̀yọ́ weighbridge")
    code, said = audit_verify(capsys)
    assert code == 0, said
    first = session.scalars(select(AuditCheckpoint)).one()
    stations(session, "Kano weighbridge", "Aba weighbridge")
    code, said = audit_verify(capsys)
    assert code == 0, said
    second = session.scalars(select(AuditCheckpoint).order_by(AuditCheckpoint.id.desc())).first()
    assert second is not None
    assert second.event_id > first.event_id
    stations(session, "Ilorin weighbridge")

    # An event after the first checkpoint and up to the second: the second is the first it crosses.
    target = session.scalar(
        select(AuditEvent.id)
        .where(AuditEvent.id > first.event_id, AuditEvent.action == "station.created")
        .order_by(AuditEvent.id)  # the first such event: without an order PostgreSQL may give any
        .limit(1)
    )
    assert target is not None
    assert target <= second.event_id
    rewrite_from(owner_engine, target, '{"name": "Nobody"}')
    session.expire_all()
    assert verify_chain(_events(session)).intact  # the links alone now check from the first event

    before = checkpoint_count(session)
    code, said = audit_verify(capsys)
    assert code == 1
    assert (
        f"the chain up to event {second.event_id} was rewritten after checkpoint {second.id} was signed"
        in said
    )
    assert f"({first.event_id} events before it are intact)" in said
    assert f"checkpoint {first.id} " not in said.split("(")[0]
    assert checkpoint_count(session) == before  # nothing signed over the rewrite
    with pytest.raises(ChainContradicted, match=f"checkpoint {second.id}"):
        record_checkpoint(session, get_settings(), event_id=target)
    session.rollback()
    page = admin_web.get("/admin/audit")
    assert "The record was tampered with." in page.text


def test_a_rewrite_before_every_checkpoint_names_the_oldest(
    session: Session, owner_engine: Engine, capsys: pytest.CaptureFixture[str]
) -> None:
    stations(session, "Agbara weighbridge", "Ikeja weighbridge")
    assert audit_verify(capsys)[0] == 0
    stations(session, "Kano weighbridge")
    assert audit_verify(capsys)[0] == 0
    first = session.scalars(select(AuditCheckpoint).order_by(AuditCheckpoint.id)).first()
    assert first is not None
    rewrite_from(owner_engine, 1, '{"name": "Nobody"}')
    code, said = audit_verify(capsys)
    assert code == 1, said
    assert f"rewritten after checkpoint {first.id} was signed" in said
    assert "(0 events before it are intact)" in said


def pad(part: str) -> bytes:
    return base64.urlsafe_b64decode(part + "=" * (-len(part) % 4))


def claims_checked_outside(token: str, keys: dict[str, Any]) -> dict[str, Any]:
    """A checkpoint checked as an outside party would: Ed25519 by the published key its kid names."""
    header_b64, payload_b64, signature_b64 = token.split(".")
    header = json.loads(pad(header_b64))
    key = next(k for k in keys["keys"] if k["kid"] == header["kid"])
    Ed25519PublicKey.from_public_bytes(pad(key["x"])).verify(
        pad(signature_b64), f"{header_b64}.{payload_b64}".encode()
    )
    claims: dict[str, Any] = json.loads(pad(payload_b64))
    return claims


def test_every_checkpoint_is_published_and_each_names_the_one_before(
    client: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    assert client.get("/api/v1/audit/checkpoints").json() == {"checkpoints": [], "more": False}
    for name in ("Agbara weighbridge", "Ikeja weighbridge", "Kano weighbridge"):
        stations(session, name)
        assert audit_verify(capsys)[0] == 0
    answer = client.get("/api/v1/audit/checkpoints")
    assert answer.status_code == 200
    assert answer.headers["Cache-Control"] == "public, max-age=60"
    published = answer.json()["checkpoints"]
    assert len(published) == 3
    keys = client.get("/.well-known/trikecert-keys.json").json()
    previous = None
    for checkpoint in published:
        claims = claims_checked_outside(checkpoint["token"], keys)
        assert (claims["event"], claims["hash"]) == (checkpoint["event_id"], checkpoint["hash"])
        expected = hashlib.sha256(previous["token"].encode()).hexdigest() if previous else None
        assert claims["previous"] == expected
        previous = checkpoint
    assert client.get("/api/v1/audit/head").json() == published[-1]
    later = client.get("/api/v1/audit/checkpoints", params={"after": published[0]["checkpoint"]}).json()
    assert later["checkpoints"] == published[1:]
    refused = client.get("/api/v1/audit/checkpoints", params={"after": "-1"})
    assert refused.status_code == 422
    assert "after" in refused.text
