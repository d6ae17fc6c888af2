"""The text rule as an officer meets it in a real browser (Chromium through Playwright): text pasted
with a hidden character comes back with the message beside the field and nothing is stored."""

from __future__ import annotations

import pytest
from playwright.sync_api import Page, expect
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.vehicles.models import Vehicle
from web.webtools import OFFICER_EMAIL, PASSWORD

pytestmark = pytest.mark.browser


def test_a_make_pasted_with_a_right_to_left_override_is_refused_beside_the_field(
    page: Page, officer: User, session: Session
) -> None:
    page.goto("/login")
    page.get_by_label("Email address").fill(OFFICER_EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()
    page.goto("/vehicles/new")
    page.locator("#registration_number").fill("KTU 417 XA")
    page.locator("#make").fill("Baj\u202eaj")  # shown as "Bajja" by a browser: it reads backwards
    page.locator("#model").fill("RE")
    page.locator("#wheelbase_m").fill("2.000")
    page.locator("#driver_x_m").fill("0.930")
    page.get_by_role("button", name="Register vehicle").click()
    message = page.locator("#make-error")
    expect(message).to_contain_text("Remove the text-direction control U+202E (RIGHT-TO-LEFT OVERRIDE)")
    expect(page.locator("#make")).to_have_value("Bajaj")  # shown again without it, to check and send
    expect(page.locator(".error-summary")).to_contain_text("U+202E")
    session.expire_all()
    assert session.scalar(select(func.count()).select_from(Vehicle)) == 0
