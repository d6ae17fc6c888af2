"""Who a web request is recorded as: a sign-in, good or failed, by nobody signed in (with the client's
address), what follows by the officer; never the account that started `trikecert serve`."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from fastapi.testclient import TestClient
from served import free_port, wait_until_ready
from sqlalchemy import Engine, select
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.audit.models import AuditEvent
from app.audit.recorder import acting_from_command_line
from app.main import create_app
from web.webtools import OFFICER_EMAIL, PASSWORD, hidden

REPO = Path(__file__).resolve().parents[2]


def who_did_what(session: Session) -> list[tuple[str, str, str]]:
    """Each event's (actor kind, actor label, action), oldest first."""
    session.expire_all()
    rows = session.execute(
        select(AuditEvent.actor_kind, AuditEvent.actor_label, AuditEvent.action).order_by(AuditEvent.id)
    )
    return [(kind, label, action) for kind, label, action in rows]


def sign_in_then_out(client: httpx.Client | TestClient) -> None:
    """A wrong password, the right one, then signing out: as an officer at a browser would."""
    for password, status in (("not the password", 401), (PASSWORD, 303)):
        page = client.get("/login")
        form = {"email": OFFICER_EMAIL, "password": password, "csrf_token": hidden(page.text)}
        assert client.post("/login", data=form, follow_redirects=False).status_code == status
    home = client.get("/")
    assert home.status_code == 200
    signed_out = client.post("/logout", data={"csrf_token": hidden(home.text)}, follow_redirects=False)
    assert signed_out.status_code == 303


EXPECTED = [
    ("anonymous", "not signed in", "sign_in.bad_credentials"),
    ("anonymous", "not signed in", "sign_in.success"),
    ("user", OFFICER_EMAIL, "sign_out"),
]


def test_an_app_started_inside_the_command_line_records_sign_ins_by_nobody_then_the_officer(
    engine: Engine, session: Session, officer: User
) -> None:
    # `trikecert serve` runs the app inside the command line's actor, as this does.
    with acting_from_command_line(), TestClient(create_app(), raise_server_exceptions=False) as client:
        sign_in_then_out(client)
    assert who_did_what(session)[-3:] == EXPECTED
    addresses = session.scalars(
        select(AuditEvent.client_address).where(AuditEvent.action.startswith("sign_in."))
    ).all()
    assert addresses == ["testclient", "testclient"]


@pytest.fixture
def served(engine: Engine, database_url: str) -> Iterator[str]:
    """`trikecert serve` (one worker, the default) on the test database; yields its base URL."""
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "serve", "--port", str(port), "--no-migrate"],
        env=dict(os.environ, TRIKECERT_DATABASE_URL=database_url),
        cwd=REPO,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        wait_until_ready(f"{base}/readyz", server)
        yield base
    finally:
        server.terminate()
        server.wait(timeout=30)


def test_a_served_sign_in_is_recorded_by_nobody_with_the_address_then_the_officer(
    served: str, session: Session, officer: User
) -> None:
    with httpx.Client(base_url=served, timeout=10) as browser:
        sign_in_then_out(browser)
    recorded = who_did_what(session)
    assert recorded[-3:] == EXPECTED
    assert not [event for event in recorded if event[0] == "command_line" and event[2] != "service.started"]
    addresses = session.scalars(
        select(AuditEvent.client_address).where(AuditEvent.action.startswith("sign_in."))
    ).all()
    assert addresses == ["127.0.0.1", "127.0.0.1"]
