"""Re-authentication before what cannot be undone: once the session's last check is over five
minutes old, a station's new key, another account's password or second factor, and a new account
ask for the password, and a current code when the account has a second factor, before they go ahead."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.audit.models import AuditEvent
from app.stations.models import Station
from web.webtools import (
    ADMIN_EMAIL,
    OFFICER_EMAIL,
    PASSWORD,
    code_at,
    enrol_with_code,
    form_values,
    hidden,
    make_stale,
    sign_in,
)


def key_hash(session: Session, station: Station) -> str:
    session.expire_all()
    found = session.get(Station, station.id)
    assert found is not None
    return found.key_hash


def test_a_fresh_session_rotates_a_key_without_being_asked_again(
    admin_web: TestClient, session: Session, station: Station
) -> None:
    before = key_hash(session, station)
    make_stale(session, minutes=4)
    page = admin_web.get(f"/admin/stations/{station.id}")
    rotated = admin_web.post(f"/admin/stations/{station.id}/key", data={"csrf_token": hidden(page.text)})
    assert rotated.status_code == 200
    assert "Confirm it is you" not in rotated.text
    assert key_hash(session, station) != before


def test_an_enrolled_admin_confirms_a_key_rotation_with_password_and_a_new_code(
    client: TestClient, admin: User, session: Session, station: Station, required: None
) -> None:
    assert sign_in(client, ADMIN_EMAIL).status_code == 303
    secret, _codes, used = enrol_with_code(client)  # `used` is used up here
    before = key_hash(session, station)
    make_stale(session)
    page = client.get(f"/admin/stations/{station.id}")
    asked = client.post(f"/admin/stations/{station.id}/key", data={"csrf_token": hidden(page.text)})
    assert asked.status_code == 401
    assert 'id="reauth_code"' in asked.text
    assert 'id="reauth_password"' in asked.text
    assert key_hash(session, station) == before

    no_code = client.post(
        f"/admin/stations/{station.id}/key", data={**form_values(asked.text), "reauth_password": PASSWORD}
    )
    assert no_code.status_code == 422
    assert "Enter the 6-digit code your app shows now" in no_code.text

    replayed = {**form_values(asked.text), "reauth_password": PASSWORD, "reauth_code": used}
    refused = client.post(f"/admin/stations/{station.id}/key", data=replayed)
    assert refused.status_code == 422
    assert "not right or was used already" in refused.text
    assert key_hash(session, station) == before

    fresh = {**form_values(asked.text), "reauth_password": PASSWORD, "reauth_code": code_at(secret)}
    done = client.post(f"/admin/stations/{station.id}/key", data=fresh)
    assert done.status_code == 200, done.text
    assert key_hash(session, station) != before
    session.expire_all()
    actions = session.scalars(select(AuditEvent.action).order_by(AuditEvent.id)).all()
    assert actions[-2:] == ["user.reauthenticated", "station.key_rotated"]


@pytest.mark.parametrize(
    ("path", "fields", "outcome"),
    [
        (
            "/admin/users/{officer}/password",
            {"password": "a brand new passphrase"},
            "New password set for officer@example.org",
        ),
        ("/admin/users/{officer}/two-factor/reset", {}, "The second factor of officer@example.org was reset"),
        (
            "/admin/users/new",
            {"email": "new@example.org", "name": "Ada Obi", "role": "admin", "password": PASSWORD},
            "Account new@example.org (admin) created.",
        ),
    ],
)
def test_a_stale_admin_is_asked_again_before_changing_an_account(
    admin_web: TestClient, officer: User, session: Session, path: str, fields: dict[str, str], outcome: str
) -> None:
    url = path.format(officer=officer.id)
    before = session.scalars(select(AuditEvent.id).order_by(AuditEvent.id.desc()).limit(1)).one()
    make_stale(session)
    token = hidden(admin_web.get("/admin/users").text)
    asked = admin_web.post(url, data={"csrf_token": token, **fields})
    assert asked.status_code == 401
    assert "<h1>Confirm it is you</h1>" in asked.text
    assert 'type="password"' in asked.text
    session.expire_all()
    assert session.scalars(select(AuditEvent.id).where(AuditEvent.id > before)).all() == []  # nothing done
    done = admin_web.post(url, data={**form_values(asked.text), "reauth_password": PASSWORD})
    assert done.status_code == 200, done.text
    assert outcome in done.text
    session.expire_all()
    since = select(AuditEvent.action).where(AuditEvent.id > before)
    after = session.scalars(since.order_by(AuditEvent.id)).all()
    assert after[0] == "user.reauthenticated"


def test_an_officer_is_refused_before_being_asked_to_confirm(web: TestClient, session: Session) -> None:
    make_stale(session)
    token = hidden(web.get("/").text)
    refused = web.post("/admin/users/new", data={"csrf_token": token, "email": "x@example.org"})
    assert refused.status_code == 403
    assert "Confirm it is you" not in refused.text


def test_a_confirmation_page_carries_the_form_safely(admin_web: TestClient, session: Session) -> None:
    make_stale(session)
    token = hidden(admin_web.get("/admin/users").text)
    typed = '"><script>alert(1)</script>'
    asked = admin_web.post("/admin/users/new", data={"csrf_token": token, "email": typed})
    assert asked.status_code == 401
    assert "<script>alert(1)</script>" not in asked.text
    assert form_values(asked.text)["email"] == typed
    assert OFFICER_EMAIL not in asked.text
