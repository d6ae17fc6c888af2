"""In the officers' pages: issue an inspection's certificate, download its PDF, and (admins) revoke it."""

from __future__ import annotations

from certificate_helpers import register, weigh
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session
from web.webtools import ADMIN_EMAIL, OFFICER_EMAIL, PASSWORD, form_values, hidden, make_stale, sign_in

from app.accounts.service import create_user
from app.audit.models import AuditEvent


def signed_in(client: TestClient, session: Session, role: str) -> str:
    email = ADMIN_EMAIL if role == "admin" else OFFICER_EMAIL
    create_user(session, email=email, password=PASSWORD, role=role)
    assert sign_in(client, email).status_code == 303
    return hidden(client.get("/").text)


def issue_from_page(api: TestClient, session: Session, role: str) -> tuple[str, str]:
    register(api)
    inspection_id = weigh(api)
    api.headers.pop("Authorization")
    token = signed_in(api, session, role)
    issued = api.post(
        f"/inspections/{inspection_id}/certificate", data={"csrf_token": token}, follow_redirects=False
    )
    assert issued.status_code == 303
    return issued.headers["location"], token


def test_an_officer_issues_a_refusal_and_downloads_its_pdf(api: TestClient, session: Session) -> None:
    location, _token = issue_from_page(api, session, "officer")
    number = location.rsplit("/", 1)[1]
    page = api.get(location)
    assert page.status_code == 200
    assert f"<p>Refusal {number} issued.</p>" in page.text
    assert "Certificate TRK-" not in page.text
    assert 'id="headline">NOT CERTIFIED: refusal</h1>' in page.text
    assert "Download the PDF" in page.text
    assert "Revoke this" not in page.text
    pdf = api.get(f"{location}/pdf")
    assert pdf.status_code == 200
    assert pdf.content.startswith(b"%PDF-")
    assert api.get(f"{location}/pdf", headers={"If-None-Match": pdf.headers["etag"]}).status_code == 304


def test_a_form_post_without_the_csrf_token_issues_nothing(api: TestClient, session: Session) -> None:
    register(api)
    inspection_id = weigh(api)
    api.headers.pop("Authorization")
    signed_in(api, session, "officer")
    assert api.post(f"/inspections/{inspection_id}/certificate", data={}).status_code == 403


def test_an_admin_revokes_with_a_reason_and_the_public_page_says_revoked(
    api: TestClient, session: Session
) -> None:
    location, token = issue_from_page(api, session, "admin")
    number = location.rsplit("/", 1)[1]
    assert "Revoke this refusal" in api.get(location).text
    missing = api.post(f"{location}/revoke", data={"csrf_token": token, "reason": "  "})
    assert missing.status_code == 422
    assert "Enter the reason for revoking this refusal" in missing.text
    done = api.post(f"{location}/revoke", data={"csrf_token": token, "reason": "Forged weighbridge ticket"})
    assert done.status_code == 200
    assert f"<p>Refusal {number} revoked.</p>" in done.text
    assert 'id="headline">REVOKED on ' in done.text
    api.cookies.clear()
    public = api.get(f"/verify/{number}")
    assert 'id="headline">REVOKED on ' in public.text
    assert 'class="status status--revoked"' in public.text
    assert "Forged weighbridge ticket" in public.text
    assert "Download the PDF" not in public.text


def test_an_officer_cannot_revoke(api: TestClient, session: Session) -> None:
    location, token = issue_from_page(api, session, "officer")
    refused = api.post(f"{location}/revoke", data={"csrf_token": token, "reason": "I would like to"})
    assert refused.status_code == 403
    assert 'id="headline">NOT CERTIFIED: refusal</h1>' in api.get(location).text


def test_revoking_after_five_minutes_asks_for_the_password_again_then_goes_ahead(
    api: TestClient, session: Session
) -> None:
    location, token = issue_from_page(api, session, "admin")
    make_stale(session)
    asked = api.post(f"{location}/revoke", data={"csrf_token": token, "reason": "Forged ticket"})
    assert asked.status_code == 401
    assert "<h1>Confirm it is you</h1>" in asked.text
    assert 'name="reason" value="Forged ticket"' in asked.text  # the form goes on with what was typed
    assert 'id="headline">NOT CERTIFIED: refusal</h1>' in api.get(location).text  # not revoked yet

    carried = {**form_values(asked.text), "reauth_password": "not my password"}
    wrong = api.post(f"{location}/revoke", data=carried)
    assert wrong.status_code == 422
    assert "That is not your password" in wrong.text
    assert 'aria-describedby="reauth_password-error"' in wrong.text
    assert 'id="headline">NOT CERTIFIED: refusal</h1>' in api.get(location).text

    carried = {**form_values(wrong.text), "reauth_password": PASSWORD}
    done = api.post(f"{location}/revoke", data=carried)
    assert done.status_code == 200, done.text
    assert "revoked." in done.text
    actions = session.scalars(select(AuditEvent.action).order_by(AuditEvent.id)).all()
    assert actions[-3:] == [
        "user.reauthentication_failed",
        "user.reauthenticated",
        "certificate.revoked",
    ]
    number = location.rsplit("/", 1)[1]
    revoked = select(AuditEvent.target_id).where(AuditEvent.action == "certificate.revoked")
    assert session.scalars(revoked).all() == [number]  # found by the number people know it by


def test_wrong_confirming_passwords_count_towards_the_lock_out(api: TestClient, session: Session) -> None:
    location, token = issue_from_page(api, session, "admin")
    make_stale(session)
    form = {"csrf_token": token, "reason": "Forged ticket", "reauth_password": "guess"}
    statuses = [api.post(f"{location}/revoke", data=form).status_code for _ in range(6)]
    assert statuses[:5] == [422] * 5
    locked = api.post(f"{location}/revoke", data={**form, "reauth_password": PASSWORD})
    assert locked.status_code == 422
    assert "too many wrong passwords" in locked.text.lower()
    assert 'id="headline">NOT CERTIFIED: refusal</h1>' in api.get(location).text
