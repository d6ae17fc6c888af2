"""Who did what, through the service's doors: officers' pages, a station's API calls and sign-ins
land in the audit log that admins read, and any edit of the log is shown as tampering."""

from __future__ import annotations

import base64
import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey
from fastapi.testclient import TestClient
from sqlalchemy import Engine, select, text
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session
from study_data import STUDY_VEHICLE

from app.accounts.models import User
from app.audit.models import AuditCheckpoint, AuditEvent
from app.audit.recorder import acting_from_command_line
from app.audit.service import verify_log
from app.audit.startup import record_start
from app.certificates.guard import immutability_lifted
from app.config import Settings
from app.stations.service import create_station
from web.webtools import ADMIN_EMAIL, PASSWORD, hidden, post_form, sign_in

BIN = Path(sys.executable).parent


def events(session: Session) -> list[AuditEvent]:
    session.expire_all()
    return list(session.scalars(select(AuditEvent).order_by(AuditEvent.id)))


def test_admin_actions_station_calls_and_sign_ins_are_recorded_with_who_did_them(
    admin_web: TestClient, admin: User, client: TestClient, session: Session
) -> None:
    post_form(
        admin_web,
        "/admin/users/new",
        "/admin/users/new",
        {
            "email": "new.officer@example.org",
            "name": "Ngozi Eze",
            "role": "officer",
            "password": "a long enough secret",
        },
    )
    station, key = create_station(session, name="Ọ̀yọ́ weighbridge")
    page = admin_web.get(f"/admin/stations/{station.id}")
    fields = {"csrf_token": hidden(page.text), "form_token": hidden(page.text, "form_token")}
    rotated = admin_web.post(f"/admin/stations/{station.id}/key", data=fields, follow_redirects=False)
    assert rotated.status_code == 200
    new_key = rotated.text.split("tks_", 1)[1].split("<", 1)[0]
    station_api = TestClient(client.app, headers={"Authorization": f"Bearer tks_{new_key}"})
    assert station_api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    stranger = TestClient(client.app)
    assert sign_in(stranger, ADMIN_EMAIL, "not the password").status_code == 401

    recorded = [(e.actor_kind, e.actor_label, e.action, e.target_type) for e in events(session)]
    assert ("user", ADMIN_EMAIL, "user.created", "user") in recorded
    assert ("user", ADMIN_EMAIL, "station.key_rotated", "station") in recorded
    assert ("station", "Ọ̀yọ́ weighbridge", "vehicle.created", "vehicle") in recorded
    assert ("anonymous", "not signed in", "sign_in.bad_credentials", "user") in recorded
    assert ("anonymous", "not signed in", "sign_in.success", "user") in recorded  # the admin's own
    created = next(e for e in events(session) if e.action == "user.created" and e.actor_kind == "user")
    assert json.loads(created.details) == {
        "email": "new.officer@example.org",
        "role": "officer",
        "active": True,
    }
    rotation = next(e for e in events(session) if e.action == "station.key_rotated")
    assert json.loads(rotation.details)["key_hash"] == "(changed)"  # never the key or its hash
    assert key not in rotation.details

    audit_page = admin_web.get("/admin/audit")
    assert audit_page.status_code == 200
    assert "The record is intact." in audit_page.text
    assert f"All {len(recorded)} events were checked" in audit_page.text
    assert "station: key rotated" in audit_page.text
    assert "Ọ̀yọ́ weighbridge" in audit_page.text


def test_an_officer_cannot_read_the_audit_log(web: TestClient) -> None:
    assert web.get("/admin/audit").status_code == 403


def test_an_edited_event_is_shown_as_tampering_on_the_page_and_by_the_command(
    admin_web: TestClient, owner_engine: Engine, session: Session, database_url: str
) -> None:
    create_station(session, name="Agbara weighbridge")
    create_station(session, name="Ikeja weighbridge")
    target = next(e for e in events(session) if e.action == "station.created")
    with owner_engine.begin() as connection, immutability_lifted(connection):
        connection.execute(
            text("UPDATE audit_event SET details = :d WHERE id = :id"),
            {"d": '{"name": "Nobody"}', "id": target.id},
        )

    page = admin_web.get("/admin/audit")
    assert "The record was tampered with." in page.text
    assert f"Event {target.id} was changed after it was recorded" in page.text
    done = subprocess.run(
        [BIN / "trikecert", "audit-verify"],
        env={"TRIKECERT_DATABASE_URL": database_url, "PATH": str(BIN)},
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 1
    assert f"event {target.id} was changed after it was recorded" in done.stdout


@pytest.mark.parametrize("statement", ["UPDATE audit_event SET action = 'x'", "DELETE FROM audit_event"])
def test_the_database_refuses_to_change_or_delete_an_event_even_for_its_owner(
    owner_engine: Engine, session: Session, statement: str
) -> None:
    create_station(session, name="Agbara weighbridge")
    refused = pytest.raises(DBAPIError, match="audit events are never changed or deleted")
    with refused, owner_engine.begin() as c:
        c.execute(text(statement))
    assert len(events(session)) == 1


def test_the_command_says_an_untouched_log_is_intact(session: Session, database_url: str) -> None:
    create_station(session, name="Agbara weighbridge")
    done = subprocess.run(
        [BIN / "trikecert", "audit-verify"],
        env={"TRIKECERT_DATABASE_URL": database_url, "PATH": str(BIN)},
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == "the audit log is intact: 1 events checked"


def test_each_event_carries_the_client_address_and_the_request_id_of_the_access_log(
    client: TestClient, admin: User, session: Session
) -> None:
    page = client.get("/login")
    signed = client.post(
        "/login",
        data={"email": ADMIN_EMAIL, "password": PASSWORD, "csrf_token": hidden(page.text)},
        headers={"X-Request-ID": "walk-7f3a"},
        follow_redirects=False,
    )
    assert signed.status_code == 303
    assert signed.headers["X-Request-ID"] == "walk-7f3a"
    sign_ins = [e for e in events(session) if e.action == "sign_in.success"]
    assert [(e.client_address, e.request_id) for e in sign_ins] == [("testclient", "walk-7f3a")]
    assert verify_log(session).intact


def test_signing_out_is_recorded(web: TestClient, session: Session) -> None:
    signed_out = web.post("/logout", data={"csrf_token": hidden(web.get("/").text)}, follow_redirects=False)
    assert signed_out.status_code == 303
    last = events(session)[-1]
    assert (last.actor_label, last.action, last.target_type) == ("officer@example.org", "sign_out", "user")


def test_the_settings_in_force_at_start_are_recorded_without_any_secret(
    session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TRIKECERT_METRICS_TOKEN", "metrics-token-that-is-secret")
    monkeypatch.setenv("TRIKECERT_DISPLAY_TIMEZONE", "Africa/Accra")
    settings = Settings()
    with acting_from_command_line():
        record_start(session, settings)
    started = events(session)[-1]
    assert (started.actor_kind, started.action) == ("command_line", "service.started")
    details = json.loads(started.details)
    assert details["settings"]["display_timezone"] == "Africa/Accra"
    assert details["settings"]["metrics_token"] == "(set)"
    assert details["settings"]["mfa"] == settings.mfa_mode()
    assert "metrics-token-that-is-secret" not in started.details
    assert verify_log(session).intact


def audit_verify(database_url: str) -> subprocess.CompletedProcess[str]:
    """`trikecert audit-verify`, as an operator runs it."""
    return subprocess.run(
        [BIN / "trikecert", "audit-verify"],
        env={"TRIKECERT_DATABASE_URL": database_url, "PATH": str(BIN)},
        capture_output=True,
        text=True,
        check=False,
    )


def independent_claims(token: str, jwks: dict[str, Any]) -> dict[str, Any]:
    """A checkpoint token checked as a regulator would: Ed25519 over `header.payload`, by the key
    its kid names."""
    header_b64, payload_b64, signature_b64 = token.split(".")

    def pad(part: str) -> bytes:
        return base64.urlsafe_b64decode(part + "=" * (-len(part) % 4))

    header = json.loads(pad(header_b64))
    key = next(k for k in jwks["keys"] if k["kid"] == header["kid"])
    Ed25519PublicKey.from_public_bytes(pad(key["x"])).verify(
        pad(signature_b64), f"{header_b64}.{payload_b64}".encode()
    )
    claims: dict[str, Any] = json.loads(pad(payload_b64))
    return claims


def test_a_full_check_signs_a_checkpoint_that_is_published_and_verifies_by_the_published_key(
    client: TestClient, session: Session, database_url: str
) -> None:
    assert client.get("/api/v1/audit/head").status_code == 404
    create_station(session, name="Agbara weighbridge")
    create_station(session, name="Ikeja weighbridge")
    done = audit_verify(database_url)
    assert done.returncode == 0, done.stderr
    head = events(session)[1]  # the second station: the last event before the signing key was made
    assert re.search(rf"^checkpoint \d+ signed at event {head.id}: {head.hash}$", done.stdout, re.M)
    published = client.get("/api/v1/audit/head")
    assert published.status_code == 200
    body = published.json()
    assert (body["event_id"], body["hash"]) == (head.id, head.hash)
    claims = independent_claims(body["token"], client.get("/.well-known/trikecert-keys.json").json())
    assert (claims["chain"], claims["event"], claims["hash"]) == ("trikecert-audit", head.id, head.hash)


def test_the_page_checks_from_the_checkpoint_and_finds_the_newest_events_cut_off(
    admin_web: TestClient, owner_engine: Engine, session: Session, database_url: str
) -> None:
    create_station(session, name="Agbara weighbridge")
    assert audit_verify(database_url).returncode == 0
    checkpoint = session.scalars(select(AuditCheckpoint)).one()
    signed_at = checkpoint.event_id
    page = admin_web.get("/admin/audit")
    assert f"at event {signed_at}, holds" in page.text
    with owner_engine.begin() as connection, immutability_lifted(connection):
        connection.execute(text("DELETE FROM audit_event WHERE id >= :id"), {"id": signed_at})
    # What is left is a chain that checks from the first event; the checkpoint shows what was cut.
    page = admin_web.get("/admin/audit")
    assert "The record was tampered with." in page.text
    assert f"Event {signed_at} is missing: checkpoint {checkpoint.id} was signed at it" in page.text
    done = audit_verify(database_url)
    assert done.returncode == 1
    assert (
        f"event {signed_at} is missing: checkpoint {checkpoint.id} was signed at event {signed_at}"
        in done.stdout
    )


def test_a_forged_checkpoint_is_refused_on_the_page(
    admin_web: TestClient, owner_engine: Engine, session: Session, database_url: str
) -> None:
    create_station(session, name="Agbara weighbridge")
    assert audit_verify(database_url).returncode == 0
    with owner_engine.begin() as connection, immutability_lifted(connection):
        connection.execute(text("UPDATE audit_checkpoint SET hash = :h"), {"h": "0" * 64})
    checkpoint = session.scalars(select(AuditCheckpoint)).one()
    page = admin_web.get("/admin/audit")
    assert f"Checkpoint {checkpoint.id} is not as a published key signed it" in page.text
