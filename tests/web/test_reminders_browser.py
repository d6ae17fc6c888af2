"""The public /reminders page walked in Debian's Chromium as a keke owner would: a bad plate and email are
refused beside their fields and nothing is kept; then an address is subscribed, the confirmation email
arrives at a real SMTP server (aiosmtpd), its link is followed, a reminder arrives, and its one-click
link stops the reminders. axe-core finds nothing on each page, and none scrolls sideways at 360 px; with
TRIKECERT_SCREENSHOTS=1 they are saved at 1280 and 360 px in docs/screenshots/reminders/."""

from __future__ import annotations

import re
from collections.abc import Iterator
from datetime import datetime, timedelta
from decimal import Decimal
from pathlib import Path

import pytest
from notifications.servers import Mailbox, outside_services, senders
from playwright.sync_api import Page, expect
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate
from app.db import get_sessionmaker, utcnow
from app.inspections.service import InspectionRequest, record_inspection
from app.notifications.models import OutboxMessage, Subscription
from app.notifications.worker import Pass, run_once
from app.vehicles.service import register_vehicle
from web.webtools import (
    SCREENSHOTS,
    STUDY_SEATS,
    TAKE_SCREENSHOTS,
    axe_violations,
    save_at_both_widths,
    wheel_readings,
)

pytestmark = pytest.mark.browser

NARROW = 360
FOLDER = SCREENSHOTS / "reminders"
TYPED = "Ada.Obi@Example.NG"
ADDRESS = "Ada.Obi@example.ng"  # as normalised: the domain in small letters


@pytest.fixture
def mail(monkeypatch: pytest.MonkeyPatch, live_server: str) -> Iterator[Mailbox]:
    """The SMTP server running, the worker's settings pointing at it, links pointing at the live server."""
    with outside_services(monkeypatch, TRIKECERT_BASE_URL=live_server) as (mailbox, _gateway):
        yield mailbox


@pytest.fixture
def expires(session: Session) -> datetime:
    """KTU 417 XA certified (every case complies); when its certificate expires."""
    register_vehicle(
        session,
        registration_number="KTU 417 XA",
        make="TVS",
        model="King Deluxe",
        model_year=2019,
        wheelbase_m=Decimal("2.000"),
        seats=STUDY_SEATS,
    )
    readings = wheel_readings(200, 80, 80, 360)
    request = InspectionRequest(registration_number="KTU 417 XA", readings=readings)
    inspection = record_inspection(session, request=request, rules=config.get_settings().rules())
    issued = issue_certificate(
        session, inspection_id=inspection.id, actor=Actor.of_cli(), settings=config.get_settings()
    )
    assert issued.certificate.kind == "compliant"
    return issued.certificate.expires_at


def worker_pass(at: datetime) -> Pass:
    """One pass of `trikecert notify` with its clock at `at`."""
    return run_once(get_sessionmaker(), senders(2), config.get_settings(), now=lambda: at)


def look(page: Page, name: str, axe: Path) -> None:
    """axe-core finds nothing; at 360 px nothing sticks out sideways; saved when screenshots are asked for."""
    assert axe_violations(page, axe) == [], name
    page.set_viewport_size({"width": NARROW, "height": 740})
    assert page.evaluate("document.documentElement.scrollWidth") <= NARROW, name
    page.set_viewport_size({"width": 1280, "height": 900})
    if TAKE_SCREENSHOTS:
        save_at_both_widths(page, FOLDER, name)


def refused_beside(page: Page, field: str, words: str) -> None:
    """The field's own message says `words`, inside its group, and the summary links to the field."""
    group = page.locator(".form-group", has=page.locator(f"#{field}"))
    expect(group.locator(f"#{field}-error")).to_contain_text(words)
    assert f"{field}-error" in (page.locator(f"#{field}").get_attribute("aria-describedby") or "")
    expect(page.locator(f'.error-summary a[href="#{field}"]')).to_contain_text(words)


def nothing_stored(session: Session) -> None:
    session.expire_all()
    assert session.scalars(select(Subscription)).all() == []
    assert session.scalars(select(OutboxMessage)).all() == []


def test_an_owner_subscribes_confirms_and_unsubscribes_by_email_in_a_browser(
    audit_page: Page, axe_script: Path, session: Session, mail: Mailbox, expires: datetime, live_server: str
) -> None:
    page = audit_page
    page.goto("/reminders")
    expect(page.get_by_role("heading", name="Get reminders before a certificate expires")).to_be_visible()
    assert page.locator("script").count() == 0
    page.set_viewport_size({"width": NARROW, "height": 740})
    for keyword in page.locator(".keywords strong").all():  # sent as typed: never split over two lines
        assert keyword.evaluate("element => element.getClientRects().length") == 1, keyword.inner_text()
    look(page, "form", axe_script)

    # An unknown plate and a malformed address: each refused beside its field, what was typed kept.
    page.get_by_label("Plate").fill("ZZZ 999 ZZ")
    page.get_by_label("Email address").fill("ada.obi at example")
    page.get_by_role("button", name="Send the link").click()
    refused_beside(page, "plate", "No keke ZZZ 999 ZZ is registered: check the plate")
    refused_beside(page, "email", "Enter an email address like name@example.com")
    expect(page.locator(".error-summary a")).to_have_text(  # in the form's order, each said once
        ["No keke ZZZ 999 ZZ is registered: check the plate", "Enter an email address like name@example.com"]
    )
    expect(page.get_by_label("Plate")).to_have_value("ZZZ 999 ZZ")
    expect(page.get_by_label("Email address")).to_have_value("ada.obi at example")
    look(page, "form-errors", axe_script)
    nothing_stored(session)

    # A plate that cannot be one (a right-to-left override hidden in it), and no address at all.
    page.get_by_label("Plate").fill("KTU\u202e417 XA")
    page.get_by_label("Email address").fill("")
    page.get_by_role("button", name="Send the link").click()
    expect(page.locator("#plate-error")).to_be_visible()
    refused_beside(page, "email", "Enter your email address")
    nothing_stored(session)

    # The owner's plate, written as they like, and their address.
    page.get_by_label("Plate").fill("ktu417xa")
    page.get_by_label("Email address").fill(TYPED)
    page.get_by_role("button", name="Send the link").click()
    expect(page.get_by_role("heading", name="Check your email")).to_be_visible()
    expect(page.locator("#notice")).to_have_text(
        "We sent a link to A•••@example.ng. Open it to start the reminders for KTU 417 XA."
    )
    assert "Ada.Obi" not in page.content()
    look(page, "check-email", axe_script)

    # The worker sends the confirmation; its link, opened in the browser, starts the reminders.
    assert worker_pass(utcnow()).sent == 1
    [confirmation] = mail.to(ADDRESS)
    assert confirmation["Subject"] == "Confirm reminders for KTU 417 XA"
    link = re.search(r"http://\S+/reminders/confirm/\S+", confirmation.get_content())
    assert link is not None
    assert link[0].startswith(f"{live_server}/reminders/confirm/"), link[0]
    page.goto(link[0])
    expect(page.get_by_role("heading", name="Reminders confirmed")).to_be_visible()
    expect(page.locator("#notice")).to_contain_text(
        "30 and 7 days before the certificate of KTU 417 XA expires"
    )
    look(page, "confirmed", axe_script)

    # Thirty days before the expiry a reminder comes, with its one-click link to stop them.
    assert worker_pass(expires - timedelta(days=30)).sent == 1
    reminder = mail.to(ADDRESS)[-1]
    assert "runs out in 30 days" in reminder["Subject"]
    stop = reminder["List-Unsubscribe"].strip("<>")
    assert stop.startswith(f"{live_server}/reminders/unsubscribe/")
    assert stop in reminder.get_content()
    page.goto(stop)
    expect(page.get_by_role("heading", name="Stop reminders")).to_be_visible()
    session.expire_all()
    assert session.scalars(select(Subscription)).one().confirmed_at is not None  # opening stops nothing
    look(page, "stop", axe_script)
    page.get_by_role("button", name="Stop the reminders").click()
    expect(page.get_by_role("heading", name="Reminders stopped")).to_be_visible()
    expect(page.locator("#notice")).to_have_text(
        "No more reminders about KTU 417 XA will be sent, and your address is deleted."
    )
    look(page, "unsubscribed", axe_script)

    session.expire_all()
    assert session.scalars(select(Subscription)).all() == []
    assert all(ADDRESS not in (row.recipient or "") for row in session.scalars(select(OutboxMessage)))
    assert worker_pass(expires - timedelta(days=7)).planned == 0
    assert len(mail.to(ADDRESS)) == 2
