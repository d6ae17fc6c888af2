"""Administrators add, disable, enable and reset accounts; officers cannot."""

from __future__ import annotations

from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.accounts.models import User, UserSession
from app.accounts.service import verify_password
from web.webtools import OFFICER_EMAIL, hidden, post_form, sign_in


def test_an_officer_cannot_open_the_user_pages(web: TestClient) -> None:
    response = web.get("/admin/users")
    assert response.status_code == 403
    assert "Only an administrator" in response.text
    assert ">Users</a>" not in web.get("/").text


def test_an_admin_adds_a_user_who_can_then_sign_in(admin_web: TestClient, session: Session) -> None:
    response = post_form(
        admin_web,
        "/admin/users/new",
        "/admin/users/new",
        {
            "email": "New.Officer@example.org",
            "name": "Amina Bello",
            "role": "officer",
            "password": "a long enough secret",
        },
    )
    assert response.status_code == 303
    page = admin_web.get("/admin/users")
    assert "Account new.officer@example.org (officer) created." in page.text
    admin_web.cookies.clear()
    assert sign_in(admin_web, "new.officer@example.org", "a long enough secret").status_code == 303


def test_adding_a_user_with_a_short_password_shows_the_rule(admin_web: TestClient, session: Session) -> None:
    response = post_form(
        admin_web,
        "/admin/users/new",
        "/admin/users/new",
        {"email": "x@example.org", "name": "Amina Bello", "password": "short"},
    )
    assert response.status_code == 422
    assert '<a href="#password">Use at least 10 characters</a>' in response.text
    assert session.scalar(select(User).where(User.email == "x@example.org")) is None


def test_disabling_a_user_signs_them_out_everywhere(
    admin_web: TestClient, officer: User, session: Session, client: TestClient
) -> None:
    other = TestClient(client.app)
    assert sign_in(other, OFFICER_EMAIL).status_code == 303
    token = hidden(admin_web.get("/admin/users").text)
    response = admin_web.post(
        f"/admin/users/{officer.id}/disable", data={"csrf_token": token}, follow_redirects=False
    )
    assert response.status_code == 303
    assert other.get("/", follow_redirects=False).status_code == 303
    session.expire_all()
    assert session.scalars(select(UserSession).where(UserSession.user_id == officer.id)).all() == []
    assert "is disabled and has been signed out everywhere" in admin_web.get("/admin/users").text
    admin_web.post(f"/admin/users/{officer.id}/enable", data={"csrf_token": token})
    assert sign_in(other, OFFICER_EMAIL).status_code == 303


def test_an_admin_cannot_disable_their_own_account(admin_web: TestClient, admin: User) -> None:
    token = hidden(admin_web.get("/admin/users").text)
    admin_web.post(f"/admin/users/{admin.id}/disable", data={"csrf_token": token}, follow_redirects=False)
    assert "You cannot disable your own account." in admin_web.get("/admin/users").text
    assert admin_web.get("/", follow_redirects=False).status_code == 200


def test_resetting_a_password_sets_the_new_one_and_ends_the_users_sessions(
    admin_web: TestClient, officer: User, session: Session, client: TestClient
) -> None:
    other = TestClient(client.app)
    sign_in(other, OFFICER_EMAIL)
    url = f"/admin/users/{officer.id}/password"
    response = post_form(admin_web, url, url, {"password": "a brand new password"})
    assert response.status_code == 303
    session.refresh(officer)
    assert verify_password(officer.password_hash, "a brand new password")
    assert other.get("/", follow_redirects=False).status_code == 303
