"""Two-factor sign-in through the pages: enrol with a code computed from the secret on the page,
sign in with a code, a code never accepted twice, single-use recovery codes, the limit on wrong
codes, and an administrator's reset (recorded in the audit log)."""

from __future__ import annotations

from fastapi.testclient import TestClient
from httpx2 import Response
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.accounts.models import RecoveryCode, User
from app.audit.models import AuditEvent
from web.webtools import ADMIN_EMAIL, OFFICER_EMAIL, code_at, enrol, hidden, sign_in


def enter_code(client: TestClient, code: str) -> Response:
    page = client.get("/login/code")
    assert page.status_code == 200
    response: Response = client.post(
        "/login/code",
        data={"csrf_token": hidden(page.text), "next": "/", "code": code},
        follow_redirects=False,
    )
    return response


def test_a_new_officer_must_enrol_before_any_page_then_signs_in_with_a_code(
    client: TestClient, officer: User, session: Session, required: None
) -> None:
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    home = client.get("/", follow_redirects=False)
    assert home.status_code == 303
    assert home.headers["location"] == "/account/two-factor"
    secret, codes = enrol(client)
    assert len(codes) == len(set(codes)) == 10
    stored = session.scalars(select(RecoveryCode.code_hash).where(RecoveryCode.user_id == officer.id)).all()
    assert len(stored) == 10
    assert not set(codes) & set(stored)  # only hashes are kept
    assert client.get("/", follow_redirects=False).status_code == 200

    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    assert client.get("/", follow_redirects=False).headers["location"] == "/login/code"
    wrong = enter_code(client, "000000" if code_at(secret) != "000000" else "111111")
    assert wrong.status_code == 422
    assert "That code is not right or was used already" in wrong.text
    code = code_at(secret)
    assert enter_code(client, code).status_code == 303
    assert client.get("/", follow_redirects=False).status_code == 200

    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    replayed = enter_code(client, code)
    assert replayed.status_code == 422, "a code is accepted once"
    assert enter_code(client, code_at(secret, 1)).status_code == 303


def test_a_recovery_code_signs_in_once(client: TestClient, officer: User, required: None) -> None:
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    _secret, codes = enrol(client)
    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    used = enter_code(client, codes[3].lower().replace("-", " "))  # as a person might type it
    assert used.status_code == 303
    home = client.get("/")
    assert "Signed in with a recovery code; it no longer works. 9 recovery codes are left." in home.text
    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    assert enter_code(client, codes[3]).status_code == 422


def test_wrong_codes_are_limited_like_passwords(client: TestClient, officer: User, required: None) -> None:
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    secret, _codes = enrol(client)
    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    wrong = "123456" if code_at(secret) != "123456" else "654321"
    for _ in range(5):
        assert enter_code(client, wrong).status_code == 422
    locked = enter_code(client, code_at(secret, 1))
    assert locked.status_code == 422
    assert "Too many wrong codes; wait 15 minutes, then try again" in locked.text


def test_without_a_second_factor_required_an_officer_who_never_enrolled_signs_in_with_the_password(
    web: TestClient,
) -> None:
    assert web.get("/", follow_redirects=False).status_code == 200


def test_an_admin_resets_a_second_factor_and_the_officer_enrols_again(
    client: TestClient, officer: User, admin: User, session: Session, required: None
) -> None:
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    enrol(client)
    admin_browser = TestClient(client.app)
    assert sign_in(admin_browser, ADMIN_EMAIL).status_code == 303
    enrol(admin_browser)
    users = admin_browser.get("/admin/users")
    reset = admin_browser.post(
        f"/admin/users/{officer.id}/two-factor/reset",
        data={"csrf_token": hidden(users.text)},
        follow_redirects=False,
    )
    assert reset.status_code == 303
    assert "The second factor of officer@example.org was reset" in admin_browser.get("/admin/users").text
    assert client.get("/", follow_redirects=False).headers["location"] == "/account/two-factor"
    session.expire_all()
    events = session.scalars(select(AuditEvent).where(AuditEvent.action == "user.second_factor_reset")).all()
    assert [(e.actor_label, e.target_id) for e in events] == [(ADMIN_EMAIL, str(officer.id))]
