"""The study vehicle's inspection page in a real browser: the remedies in words, the form and the chart,
axe-clean; with TRIKECERT_SCREENSHOTS=1 the section is saved as docs/screenshots/remedies-<width>.png."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import pytest
from playwright.sync_api import BrowserContext, expect
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.config import get_settings
from app.inspections.service import InspectionRequest, record_inspection
from app.vehicles.models import Vehicle
from web.webtools import OFFICER_EMAIL, PASSWORD, REPO, axe_violations, wheel_readings

pytestmark = pytest.mark.browser

SCREENSHOTS = REPO / "docs" / "screenshots"


def test_the_study_vehicles_page_shows_the_remedies_and_the_chart(
    kept_context: Callable[..., BrowserContext],
    session: Session,
    study_vehicle: Vehicle,
    officer: User,
    axe_script: Path,
) -> None:
    readings = wheel_readings(108, 115, 135, 359)
    inspection = record_inspection(
        session,
        request=InspectionRequest(registration_number="BDG252QH", readings=readings),
        rules=get_settings().rules(),
    )
    page = kept_context(bypass_csp=True).new_page()
    page.goto("/login")
    page.get_by_label("Email address").fill(OFFICER_EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()
    page.goto(f"/inspections/{inspection.id}")

    section = page.locator("#remedies-section")
    expect(section.get_by_role("heading", name="What would make it comply")).to_be_visible()
    expect(section.locator("#remedies-sentence")).to_have_text(
        "Carry no more than the driver; or fit more than 54.64 kg of ballast 0.30 m behind the front wheel; "
        "or move the rear bench 0.262 m forward, which still leaves the empty vehicle non-compliant; or fit "
        "rear tyres at least 1.226 times as stiff in cornering as the front."
    )
    chart = section.get_by_role(
        "img", name="LSF per loading case today and after fitting 54.64 kg of ballast"
    )
    expect(chart).to_be_visible()
    expect(chart.locator('[data-series="after"][data-verdict="C"]')).to_have_count(5)
    expect(chart.locator('[data-series="before"][data-verdict="NC"]')).to_have_count(4)
    assert axe_violations(page, axe_script) == []

    for width in (1280, 360):
        page.set_viewport_size({"width": width, "height": 900})
        if os.environ.get("TRIKECERT_SCREENSHOTS") == "1":
            SCREENSHOTS.mkdir(parents=True, exist_ok=True)
            section.screenshot(path=str(SCREENSHOTS / f"remedies-{width}.png"))

    # The form: the driver and one passenger, ballast ahead of the wheel; then a bad position, kept.
    page.get_by_label("Occupants to certify for").fill("2")
    page.get_by_label("Ballast position (m)").fill("-0.20")
    page.get_by_label("Moving the rear bench forward").check()
    page.get_by_role("button", name="Show the remedies").click()
    expect(section.locator("#remedies-sentence")).to_contain_text(
        "fit more than 13.92 kg of ballast 0.20 m ahead"
    )
    expect(section.get_by_role("img", name="after moving the rear bench 0.191 m forward")).to_be_visible()
    page.get_by_label("Ballast position (m)").fill("far back")
    page.get_by_role("button", name="Show the remedies").click()
    expect(page.locator(".error-summary")).to_contain_text("Enter the ballast position in metres")
    expect(page.locator("#ballast_x_m-error")).to_be_visible()
    expect(page.get_by_label("Ballast position (m)")).to_have_value("far back")
    assert axe_violations(page, axe_script) == []
