"""Who did what, through the service's doors: officers' pages, a station's API calls and sign-ins
land in the audit log that admins read, and any edit of the log is shown as tampering."""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import os
import re
import subprocess
import sys
from collections.abc import Callable
from datetime import UTC, date, datetime, timedelta, timezone
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, urlencode, urlsplit
from zoneinfo import ZoneInfo

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey
from fastapi.testclient import TestClient
from sqlalchemy import Engine, select, text
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session
from study_data import STUDY_VEHICLE

from app.accounts.models import User
from app.audit import recorder
from app.audit.models import AuditCheckpoint, AuditEvent
from app.audit.recorder import Actor, act_as, acting_from_command_line, record_event
from app.audit.startup import record_start
from app.audit_log import views as audit_views
from app.audit_log.service import verify_log
from app.certificates.guard import immutability_lifted
from app.config import Settings
from app.stations.service import create_station
from web.webtools import ADMIN_EMAIL, PASSWORD, hidden, post_form, sign_in

BIN = Path(sys.executable).parent


def operator_environment(database_url: str) -> dict[str, str]:
    """What an operator's shell holds to run `trikecert`: the database and where the signing key is."""
    return {
        "TRIKECERT_DATABASE_URL": database_url,
        "TRIKECERT_SIGNING_KEY_FILE": os.environ["TRIKECERT_SIGNING_KEY_FILE"],
        "PATH": str(BIN),
    }


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
        env=operator_environment(database_url),
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 1
    assert f"event {target.id} was changed after it was recorded" in done.stdout
    admin_web.cookies.set("trikecert_lang", "ha")
    in_hausa = html.unescape(admin_web.get("/admin/audit").text)
    assert f"An canza abin da ya faru na {target.id} bayan an rubuta shi" in in_hausa
    assert "was changed after it was recorded" not in in_hausa


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
        env=operator_environment(database_url),
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
    assert "from testclient, request walk-7f3a" in client.get("/admin/audit").text
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
        env=operator_environment(database_url),
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


# ---- the filters, the pages and the CSV ------------------------------------------------------------

LAGOS = ZoneInfo("Africa/Lagos")  # the display zone of the settings: UTC+1 all year
ROW_ID = re.compile(r"<tr>\s*<td data-label=\"#\">(\d+)</td>")


def at_lagos(text: str) -> datetime:
    """A wall-clock time in Lagos ("2026-11-23 00:30"), as a UTC moment."""
    return datetime.fromisoformat(text).replace(tzinfo=LAGOS).astimezone(UTC)


# Each event as (Lagos time, actor kind, actor label, action, record type, record id, details).
HISTORY = [
    ("2026-11-22 23:30", "user", "Ngozi.Eze@example.org", "vehicle.created", "vehicle", "BDG252QH", {}),
    ("2026-11-23 00:30", "station", "Ọ̀yọ́ weighbridge", "certificate.issued", "certificate", "TRK-1", {}),
    ("2026-11-23 23:59", "command_line", "root@records", "certificate.revoked", "certificate", "TRK-1", {}),
    ("2026-11-24 00:00", "anonymous", "not signed in", "sign_in.bad_credentials", "user", "7", {}),
    ("2026-11-24 09:00", "station", "Ikeja weighbridge", "station.key_rotated", "station", "3", {}),
    ("2026-11-24 10:00", "station", '=HYPERLINK("http://x")', "signxin.probe", "station", "-4", {"a": 1}),
]


@pytest.fixture
def history(admin_web: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch) -> list[AuditEvent]:
    """The events above, recorded as the app records them (the chain intact), after the admin's own."""
    for when, kind, label, action, target_type, target_id, details in HISTORY:
        moment = at_lagos(when)
        monkeypatch.setattr(recorder, "utcnow", lambda moment=moment: moment)
        act_as(session, Actor(kind, None, label))
        record_event(session, action=action, target_type=target_type, target_id=target_id, details=details)
        session.commit()
    return events(session)


def shown_ids(html: str) -> list[int]:
    """The event numbers in the page's table, top to bottom."""
    return [int(found) for found in ROW_ID.findall(html)]


def local_day(event: AuditEvent) -> date:
    """The event's calendar day in Lagos, worked out here apart from the app's own helpers."""
    return (event.occurred_at.astimezone(UTC) + timedelta(hours=1)).date()


FILTERS: list[tuple[dict[str, str], Callable[[AuditEvent], bool]]] = [
    ({"actor": "ọ̀yọ́"}, lambda e: e.actor_label == "Ọ̀yọ́ weighbridge"),
    ({"actor": "EXAMPLE.ORG"}, lambda e: e.actor_label.lower().endswith("@example.org")),
    ({"actor_kind": "command_line"}, lambda e: e.actor_kind == "command_line"),
    ({"actor_kind": "station"}, lambda e: e.actor_kind == "station"),
    ({"action": "certificate."}, lambda e: e.action.split(".")[0] == "certificate"),
    ({"action": "sign_in."}, lambda e: e.action.split(".")[0] == "sign_in"),  # not signxin.probe
    ({"action": "certificate.revoked"}, lambda e: e.action == "certificate.revoked"),
    ({"record_type": "station"}, lambda e: e.target_type == "station"),
    ({"record_id": "TRK-1"}, lambda e: e.target_id == "TRK-1"),
    ({"record_type": "user", "record_id": "7"}, lambda e: (e.target_type, e.target_id) == ("user", "7")),
    # Lagos's 23 November runs from 22 November 23:00 UTC to 23 November 23:00 UTC.
    ({"from": "2026-11-23", "to": "2026-11-23"}, lambda e: local_day(e) == date(2026, 11, 23)),
    ({"from": "2026-11-24"}, lambda e: local_day(e) >= date(2026, 11, 24)),
    ({"to": "2026-11-22"}, lambda e: local_day(e) <= date(2026, 11, 22)),
    (
        {"actor_kind": "station", "action": "certificate.", "from": "2026-11-23", "to": "2026-11-23"},
        lambda e: (
            e.actor_kind == "station"
            and e.action.startswith("certificate.")
            and local_day(e) == date(2026, 11, 23)
        ),
    ),
    (
        {"actor": "weighbridge", "to": "2026-11-23"},
        lambda e: "weighbridge" in e.actor_label and local_day(e) <= date(2026, 11, 23),
    ),
    ({"actor": "nobody at all"}, lambda e: False),
]


@pytest.mark.parametrize(("query", "picks"), FILTERS, ids=[urlencode(q) for q, _p in FILTERS])
def test_each_filter_and_their_combinations_show_exactly_the_events_they_name(
    admin_web: TestClient,
    history: list[AuditEvent],
    query: dict[str, str],
    picks: Callable[[AuditEvent], bool],
) -> None:
    page = admin_web.get("/admin/audit", params=query)
    assert page.status_code == 200, page.text
    expected = sorted((e.id for e in history if picks(e)), reverse=True)
    assert shown_ids(page.text) == expected
    assert (f"of {len(expected)} event" in page.text) == bool(expected)
    assert "The record is intact." in page.text
    assert f"All {len(history)} events were checked" in page.text  # the whole chain, not the filtered view
    if not expected:
        assert "No events match these filters." in page.text


def test_the_midnight_between_two_days_is_the_display_zones(
    admin_web: TestClient, history: list[AuditEvent]
) -> None:
    page = admin_web.get("/admin/audit", params={"from": "2026-11-23", "to": "2026-11-23"})
    shown = {e.action for e in history if e.id in shown_ids(page.text)}
    # 22 Nov 23:30 UTC is already the 23rd in Lagos; 23 Nov 23:00 UTC is the 24th there.
    assert shown == {"certificate.issued", "certificate.revoked"}
    assert "23 November 2026, 00:30 WAT" in page.text
    assert "23 November 2026, 23:59 WAT" in page.text


def test_the_form_shows_the_filters_chosen_and_the_actions_on_record(
    admin_web: TestClient, history: list[AuditEvent]
) -> None:
    page = admin_web.get(
        "/admin/audit", params={"actor": "ikeja", "action": "certificate.", "record_type": "certificate"}
    ).text
    assert 'id="actor" name="actor" type="text" value="ikeja"' in page
    assert '<option value="certificate." selected>Any certificate action</option>' in page
    assert '<option value="certificate.revoked">certificate: revoked</option>' in page
    assert '<option value="sign_in.">Any sign in action</option>' in page
    assert '<option value="certificate" selected>Certificate</option>' in page
    assert '<option value="command_line">Command line</option>' in page


BAD_FILTERS = [
    ({"action": "certificate"}, "action", "Choose an action from the list"),
    ({"action": "Certificate.Issued"}, "action", "Choose an action from the list"),
    ({"action": "certificate.issued%"}, "action", "Choose an action from the list"),
    ({"actor_kind": "robot"}, "actor_kind", "Choose a kind of actor from the list"),
    ({"record_type": "signing key"}, "record_type", "Choose a kind of record from the list"),
    ({"from": "23/11/2026"}, "from", "Enter the date as year-month-day, like 2026-11-23"),
    ({"to": "2026-02-30"}, "to", "Enter the date as year-month-day, like 2026-11-23"),
    ({"from": "1999-12-31"}, "from", "Enter a date from 1 January 2000 to 31 December 2099"),
    (
        {"from": "2026-11-24", "to": "2026-11-23"},
        "to",
        "The 'to' date must be the same as or after the 'from' date",
    ),
    ({"actor": "adm\u202ein"}, "actor", "U+202E"),
    ({"actor": "admin\x00"}, "actor", "U+0000"),
    ({"record_id": "1" * 65}, "record_id", "Give at most 64 characters, not 65"),
    ({"action": "sign_in.\u200b"}, "action", "U+200B"),
]


@pytest.mark.parametrize(("query", "field", "message"), BAD_FILTERS, ids=[f for _q, f, _m in BAD_FILTERS])
def test_a_bad_filter_is_refused_beside_its_field_and_the_csv_refuses_it_too(
    admin_web: TestClient, history: list[AuditEvent], query: dict[str, str], field: str, message: str
) -> None:
    page = admin_web.get("/admin/audit", params=query)
    assert page.status_code == 422
    beside = re.search(rf'<p id="{field}-error" class="error-message">(.*?)</p>', page.text, re.S)
    assert beside is not None, page.text
    assert message in html.unescape(beside.group(1))
    assert f'<a href="#{field}">' in page.text  # the summary at the top leads to the field
    assert "The record is intact." in page.text
    download = admin_web.get("/admin/audit.csv", params=query)
    assert download.status_code == 422
    assert message in download.text


def test_the_pages_of_a_filtered_view_keep_the_filters(
    admin_web: TestClient, history: list[AuditEvent], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(audit_views, "PAGE_SIZE", 2)
    query = {"actor_kind": "station", "to": "2026-11-24"}
    expected = sorted((e.id for e in history if e.actor_kind == "station"), reverse=True)
    assert len(expected) == 3
    first = admin_web.get("/admin/audit", params=query).text
    assert shown_ids(first) == expected[:2]
    assert "Page 1 of 2" in first
    older = re.search(r'<a href="([^"]+)" rel="next">Older events</a>', first)
    assert older is not None
    link = html.unescape(older.group(1))
    assert parse_qs(urlsplit(link).query) == {"actor_kind": ["station"], "to": ["2026-11-24"], "page": ["2"]}
    second = admin_web.get(link).text
    assert shown_ids(second) == expected[2:]
    newer = re.search(r'<a href="([^"]+)" rel="prev">Newer events</a>', second)
    assert newer is not None
    assert parse_qs(urlsplit(html.unescape(newer.group(1))).query)["actor_kind"] == ["station"]
    csv_link = re.search(r'<a href="([^"]+)" download>Download these events \(CSV\)</a>', second)
    assert csv_link is not None
    assert parse_qs(urlsplit(html.unescape(csv_link.group(1))).query) == {
        "actor_kind": ["station"],
        "to": ["2026-11-24"],
    }


def expected_csv_row(event: AuditEvent) -> list[str]:
    """The row the CSV must hold for an event, worked out here from the stored event."""
    moment = event.occurred_at.astimezone(UTC)
    local = moment.astimezone(timezone(timedelta(hours=1)))
    label = event.actor_label
    return [
        str(event.id),
        moment.strftime("%Y-%m-%dT%H:%M:%S.%fZ"),
        local.strftime("%Y-%m-%dT%H:%M:%S.%f+01:00"),
        event.actor_kind,
        "'" + label if label[:1] in "=+-@" else label,
        event.action,
        event.target_type,
        "'" + (event.target_id or "") if (event.target_id or "")[:1] in "=+-@" else event.target_id or "",
        event.details,
        event.client_address or "",
        event.request_id or "",
        event.hash,
    ]


@pytest.mark.parametrize(
    "query",
    [{}, {"actor_kind": "station"}, {"from": "2026-11-23", "to": "2026-11-23"}, {"action": "nothing."}],
    ids=["everything", "stations", "one-day", "none"],
)
def test_the_csv_holds_every_event_of_the_filtered_view_not_one_page(
    admin_web: TestClient, history: list[AuditEvent], monkeypatch: pytest.MonkeyPatch, query: dict[str, str]
) -> None:
    monkeypatch.setattr(audit_views, "PAGE_SIZE", 1)
    page = admin_web.get("/admin/audit", params=query).text
    shown_total = re.search(r"of (\d+) events?", page)
    download = admin_web.get("/admin/audit.csv", params=query)
    assert download.status_code == 200
    assert download.headers["content-type"] == "text/csv; charset=utf-8"
    assert re.fullmatch(
        r'attachment; filename="trikecert-audit-[\w-]+\.csv"', download.headers["content-disposition"]
    )
    rows = list(csv.reader(io.StringIO(download.text)))
    assert rows[0] == [
        "id",
        "occurred_at_utc",
        "occurred_at_local",
        "actor_kind",
        "actor_label",
        "action",
        "record_type",
        "record_id",
        "details",
        "client_address",
        "request_id",
        "hash",
    ]
    ids = [int(row[0]) for row in rows[1:]]
    assert len(ids) == (int(shown_total.group(1)) if shown_total else 0)
    by_id = {e.id: e for e in history}
    assert rows[1:] == [expected_csv_row(by_id[i]) for i in sorted(ids, reverse=True)]
    if query == {"actor_kind": "station"}:
        assert len(ids) == 3


def test_a_csv_cell_a_spreadsheet_would_run_as_a_formula_is_made_plain_text(
    admin_web: TestClient, history: list[AuditEvent]
) -> None:
    download = admin_web.get("/admin/audit.csv", params={"action": "signxin.probe"})
    (row,) = list(csv.reader(io.StringIO(download.text)))[1:]
    assert row[4] == '\'=HYPERLINK("http://x")'
    assert row[7] == "'-4"
    assert row[8] == '{"a":1}'


def test_the_csv_is_for_administrators_only(client: TestClient, web: TestClient) -> None:
    assert web.get("/admin/audit.csv").status_code == 403
    assert web.get("/admin/audit", params={"action": "sign_in."}).status_code == 403
    visitor = TestClient(client.app)
    answer = visitor.get("/admin/audit.csv?action=sign_in.", follow_redirects=False)
    assert answer.status_code == 303
    assert answer.headers["location"] == "/login?" + urlencode({"next": "/admin/audit.csv?action=sign_in."})


def test_the_sign_outs_are_picked_by_their_kind_and_offered_only_so(
    admin_web: TestClient, session: Session
) -> None:
    signed_out = admin_web.post(
        "/logout", data={"csrf_token": hidden(admin_web.get("/").text)}, follow_redirects=False
    )
    assert signed_out.status_code == 303
    assert sign_in(admin_web, ADMIN_EMAIL).status_code == 303
    page = admin_web.get("/admin/audit", params={"action": "sign_out."})
    assert page.status_code == 200
    sign_outs = [event.id for event in events(session) if event.action == "sign_out"]
    assert sign_outs
    assert shown_ids(page.text) == sorted(sign_outs, reverse=True)
    assert 'value="sign_out"' not in page.text  # chosen by its kind, the one action of that kind
    assert 'value="sign_out."' in page.text
