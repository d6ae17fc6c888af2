"""Sign-in, server-side sessions, timeouts, sign-out and the lock-out, through the pages."""

from __future__ import annotations

import logging
import secrets
from datetime import timedelta

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import Engine, select, update
from sqlalchemy.orm import Session

from app import config
from app.accounts.models import LoginAttempt, LoginThrottle, User, UserSession
from app.accounts.service import set_user_active
from app.accounts.sessions import hash_token
from app.db import utcnow
from app.stations.models import Station
from web.webtools import (
    ADMIN_EMAIL,
    OFFICER_EMAIL,
    PASSWORD,
    code_at,
    enrol,
    form_values,
    hidden,
    make_stale,
    sign_in,
)


def session_cookie(client: TestClient) -> str:
    value = client.cookies.get("trikecert_session")
    assert value
    return str(value)


def test_a_page_without_a_session_sends_the_browser_to_sign_in(client: TestClient) -> None:
    response = client.get("/vehicles/find?registration_number=x", follow_redirects=False)
    assert response.status_code == 303
    assert response.headers["location"] == "/login?next=%2Fvehicles%2Ffind%3Fregistration_number%3Dx"


def test_signing_in_sets_an_httponly_samesite_cookie_and_stores_only_its_hash(
    client: TestClient, officer: User, session: Session
) -> None:
    response = sign_in(client, OFFICER_EMAIL)
    assert response.status_code == 303
    assert response.headers["location"] == "/"
    cookie = next(c for c in response.headers.get_list("set-cookie") if c.startswith("trikecert_session="))
    assert "HttpOnly" in cookie
    assert "SameSite=lax" in cookie
    assert "Secure" not in cookie  # plain http in tests
    token = session_cookie(client)
    assert len(token) >= 22  # 256 random bits, url-safe base64
    stored = session.scalars(select(UserSession)).all()
    assert [s.token_hash for s in stored] == [hash_token(token)]
    assert token not in {s.token_hash for s in stored}


def test_the_cookie_is_secure_when_the_settings_say_so(
    client: TestClient, officer: User, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TRIKECERT_COOKIE_SECURE", "true")
    config.get_settings.cache_clear()
    try:
        page = client.get("/login")
        login_cookie = page.headers["set-cookie"]
        assert login_cookie.startswith("__Host-trikecert_login_csrf=")
        assert "Secure" in login_cookie
    finally:
        monkeypatch.delenv("TRIKECERT_COOKIE_SECURE")
        config.get_settings.cache_clear()


def test_over_https_the_session_cookie_is_secure_and_host_only(client: TestClient, officer: User) -> None:
    secure = TestClient(client.app, base_url="https://testserver")
    response = sign_in(secure, OFFICER_EMAIL)
    assert response.status_code == 303
    cookie = next(c for c in response.headers.get_list("set-cookie") if "trikecert_session=" in c)
    assert cookie.startswith("__Host-trikecert_session=")
    assert "Secure" in cookie
    assert "HttpOnly" in cookie
    assert secure.get("/", follow_redirects=False).status_code == 200


def use_cookies(client: TestClient, **cookies: str) -> None:
    """Make the client's cookie jar hold exactly these cookies."""
    client.cookies.clear()
    for name, value in cookies.items():
        client.cookies.set(name, value, domain="testserver.local")


def test_signing_in_again_gives_a_new_session_id_and_ends_the_old_one(
    client: TestClient, officer: User
) -> None:
    page = client.get("/login")  # the sign-in form left open in a tab
    login_cookie, login_token = str(client.cookies.get("trikecert_login_csrf")), hidden(page.text)
    sign_in(client, OFFICER_EMAIL)
    first = session_cookie(client)
    use_cookies(client, trikecert_session=first, trikecert_login_csrf=login_cookie)
    again = client.post(
        "/login",
        data={"email": OFFICER_EMAIL, "password": PASSWORD, "csrf_token": login_token},
        follow_redirects=False,
    )
    assert again.status_code == 303
    second = session_cookie(client)
    assert second != first
    use_cookies(client, trikecert_session=first)
    assert client.get("/", follow_redirects=False).status_code == 303
    use_cookies(client, trikecert_session=second)
    assert client.get("/", follow_redirects=False).status_code == 200


def test_a_wrong_password_is_refused_with_a_message_and_no_session(client: TestClient, officer: User) -> None:
    response = sign_in(client, OFFICER_EMAIL, "wrong password!")
    assert response.status_code == 401
    assert "Enter a correct email address and password" in response.text
    assert 'href="#email"' in response.text
    assert f'value="{OFFICER_EMAIL}"' in response.text
    assert "trikecert_session" not in client.cookies


def test_signing_out_ends_the_session_on_the_server_so_a_replayed_cookie_fails(web: TestClient) -> None:
    token = session_cookie(web)
    home = web.get("/")
    out = web.post("/logout", data={"csrf_token": hidden(home.text)}, follow_redirects=False)
    assert out.status_code == 303
    assert out.headers["location"] == "/login?signed_out=1"
    use_cookies(web, trikecert_session=token)
    assert web.get("/", follow_redirects=False).status_code == 303


def test_a_session_idle_too_long_has_ended(web: TestClient, session: Session) -> None:
    record = session.scalars(select(UserSession)).one()
    record.last_seen_at = utcnow() - timedelta(minutes=31)
    session.commit()
    assert web.get("/", follow_redirects=False).status_code == 303
    session.expire_all()
    assert session.scalars(select(UserSession)).all() == []


def test_a_session_past_its_absolute_limit_has_ended_even_if_busy(web: TestClient, session: Session) -> None:
    record = session.scalars(select(UserSession)).one()
    record.expires_at = utcnow() - timedelta(seconds=1)
    session.commit()
    assert web.get("/", follow_redirects=False).status_code == 303


def test_disabling_a_user_ends_their_sessions(web: TestClient, session: Session, officer: User) -> None:
    assert web.get("/", follow_redirects=False).status_code == 200
    set_user_active(session, user=officer, active=False)
    assert session.scalars(select(UserSession)).all() == []
    assert web.get("/", follow_redirects=False).status_code == 303
    again = sign_in(web, OFFICER_EMAIL)
    assert again.status_code == 403
    assert "disabled" in again.text


def test_repeated_failures_lock_the_account_out_and_every_attempt_is_logged_without_the_password(
    client: TestClient, officer: User, session: Session, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.INFO, logger="trikecert.accounts.login")
    for _ in range(5):
        assert sign_in(client, OFFICER_EMAIL, "not the password").status_code == 401
    locked = sign_in(client, OFFICER_EMAIL)  # even the right password
    assert locked.status_code == 429
    assert "too many failed sign-ins" in locked.text
    assert "trikecert_session" not in client.cookies
    outcomes = [a.outcome for a in session.scalars(select(LoginAttempt).order_by(LoginAttempt.id))]
    assert outcomes == ["bad_credentials"] * 5 + ["locked_out"]
    assert "not the password" not in caplog.text
    assert PASSWORD not in caplog.text
    assert caplog.text.count(OFFICER_EMAIL) == 6


def test_the_lock_out_ends_when_the_window_has_passed(
    client: TestClient, officer: User, owner_engine: Engine
) -> None:
    for _ in range(5):
        sign_in(client, OFFICER_EMAIL, "not the password")
    assert sign_in(client, OFFICER_EMAIL).status_code == 429
    with owner_engine.begin() as connection:  # the app may only append login attempts
        connection.execute(update(LoginAttempt).values(created_at=utcnow() - timedelta(minutes=16)))
        connection.execute(
            update(LoginThrottle).values(last_counted_at=LoginThrottle.last_counted_at - 16 * 60)
        )
    assert sign_in(client, OFFICER_EMAIL).status_code == 303


def test_wrong_guesses_at_random_emails_behind_one_address_do_not_stop_an_officer_with_a_second_factor(
    client: TestClient, officer: User, required: None
) -> None:
    """Carrier-grade NAT: every officer of a region may share one address with whoever guesses."""
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    secret, _codes = enrol(client)
    client.cookies.clear()
    for _ in range(25):
        guess = f"{secrets.token_hex(6)}@example.org"
        assert sign_in(client, guess, secrets.token_urlsafe(12)).status_code == 401
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    page = client.get("/login/code")
    code = {"csrf_token": hidden(page.text), "next": "/", "code": code_at(secret)}
    assert client.post("/login/code", data=code, follow_redirects=False).status_code == 303
    assert client.get("/", follow_redirects=False).status_code == 200


def test_one_address_failing_on_many_accounts_is_stopped_at_its_much_higher_threshold(
    client: TestClient, officer: User, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TRIKECERT_LOGIN_ADDRESS_MAX_FAILURES", "30")  # the default, 100, takes longer
    config.get_settings.cache_clear()
    try:
        for i in range(30):
            assert sign_in(client, f"guess{i}@example.org", "password123").status_code == 401
        stopped = sign_in(client, OFFICER_EMAIL)
        assert stopped.status_code == 429
        assert "too many failed sign-ins from this network. Wait 15 minutes" in stopped.text
    finally:
        monkeypatch.delenv("TRIKECERT_LOGIN_ADDRESS_MAX_FAILURES")
        config.get_settings.cache_clear()


def test_each_check_after_the_allowance_doubles_the_account_s_wait(
    client: TestClient, officer: User, owner_engine: Engine
) -> None:
    def wait_passes(minutes: int) -> None:
        with owner_engine.begin() as connection:
            connection.execute(
                update(LoginThrottle).values(last_counted_at=LoginThrottle.last_counted_at - minutes * 60)
            )

    for _ in range(5):
        assert sign_in(client, OFFICER_EMAIL, "not the password").status_code == 401
    assert "Wait 15 minutes" in sign_in(client, OFFICER_EMAIL).text
    wait_passes(15)
    assert sign_in(client, OFFICER_EMAIL, "still not the password").status_code == 401
    locked = sign_in(client, OFFICER_EMAIL)  # the right password, too early
    assert locked.status_code == 429
    assert "too many failed sign-ins for this account. Wait 30 minutes" in locked.text
    wait_passes(16)
    assert "Wait 14 minutes" in sign_in(client, OFFICER_EMAIL).text
    wait_passes(14)
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL, "a slip after success").status_code == 401  # counting anew
    assert sign_in(client, OFFICER_EMAIL).status_code == 303


def test_a_locked_account_ends_no_session_and_its_signed_in_owner_still_confirms_it_is_them(
    admin_web: TestClient, client: TestClient, session: Session, station: Station
) -> None:
    with TestClient(client.app) as attacker:
        for _ in range(8):
            attacker.cookies.clear()
            sign_in(attacker, ADMIN_EMAIL, "a guess")
        assert sign_in(attacker, ADMIN_EMAIL).status_code == 429
    assert admin_web.get("/admin/users", follow_redirects=False).status_code == 200
    make_stale(session)
    page = admin_web.get(f"/admin/stations/{station.id}")
    asked = admin_web.post(f"/admin/stations/{station.id}/key", data={"csrf_token": hidden(page.text)})
    assert asked.status_code == 401
    done = admin_web.post(
        f"/admin/stations/{station.id}/key", data={**form_values(asked.text), "reauth_password": PASSWORD}
    )
    assert done.status_code == 200, done.text
    assert "Confirm it is you" not in done.text


def test_an_unknown_email_gets_the_same_answer_as_a_wrong_password(client: TestClient, officer: User) -> None:
    response = sign_in(client, "nobody@example.org")
    assert response.status_code == 401
    assert "Enter a correct email address and password" in response.text


def test_sign_in_returns_to_the_page_asked_for_but_never_to_another_site(
    client: TestClient, officer: User
) -> None:
    assert sign_in(client, OFFICER_EMAIL, next="/inspections").headers["location"] == "/inspections"
    client.cookies.clear()
    assert sign_in(client, OFFICER_EMAIL, next="//evil.example/").headers["location"] == "/"


def test_pages_are_never_cached(web: TestClient) -> None:
    for url in ("/", "/login", "/vehicles/find"):
        response = web.get(url)
        assert response.headers["cache-control"] == "no-store"
        assert "frame-ancestors 'none'" in response.headers["content-security-policy"]
