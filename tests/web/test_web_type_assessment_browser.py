"""In a real browser an officer assesses the study's model: pick it, see the three vehicles, confirm, and
read section 7's figures on a page axe-core finds nothing wrong with. With TRIKECERT_SCREENSHOTS=1 the
result is saved at 1280 and 360 px in docs/screenshots/type-assessment-*.png."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from playwright.sync_api import Page, expect
from sqlalchemy.orm import Session
from study_data import STUDY_TYPE_SPREAD

from app.accounts.models import User
from web.webtools import (
    ADMIN_EMAIL,
    PASSWORD,
    SCREENSHOTS,
    TAKE_SCREENSHOTS,
    axe_violations,
    weigh_study_fleet,
)

pytestmark = pytest.mark.browser


def test_an_officer_assesses_the_study_model_in_the_browser(
    audit_page: Page, axe_script: Path, session: Session, admin: User
) -> None:
    page = audit_page
    weigh_study_fleet(session)
    page.goto("/login")
    page.get_by_label("Email address").fill(ADMIN_EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()
    page.get_by_role("navigation", name="Main").get_by_role("link", name="Assess a model").click()
    expect(page.get_by_role("heading", name="Assess a model", level=1)).to_be_visible()
    page.get_by_role("link", name="Bajaj RE (2012)").click()
    vehicles = page.locator("#type-vehicles tbody tr")
    expect(vehicles).to_have_count(3)
    expect(vehicles.first).to_contain_text("AGL 532 QH")
    found = {"pick": axe_violations(page, axe_script)}

    page.get_by_role("button", name="Assess Bajaj RE (2012) from these 3 vehicles").click()
    expect(page.get_by_role("heading", level=1)).to_have_text("Bajaj RE (2012): not compliant")
    expect(page.locator("#occupancy")).to_have_text("Vehicles of this model must not carry passengers")
    rows = page.locator("#type-spread tbody tr")
    for index, (_n, low, mean, high, sd, upper, confident) in enumerate(STUDY_TYPE_SPREAD):
        cells = rows.nth(index).locator("td")
        expect(cells.nth(0)).to_have_text(f"{low:.5f}")
        expect(cells.nth(1)).to_have_text(f"{mean:.5f}")
        expect(cells.nth(2)).to_have_text(f"{high:.5f}")
        expect(cells.nth(3)).to_have_text(f"{sd:.5f}")
        expect(cells.nth(4)).to_have_text(f"{upper:.5f}")
        expect(cells.nth(5)).to_contain_text("Compliant" if confident else "Not compliant")
    expect(page.locator("#table-4 tbody tr").nth(1)).to_contain_text("283.49")
    chart = page.get_by_role("img", name="Each vehicle's LSF per loading case", exact=False)
    expect(chart).to_be_visible()
    expect(
        page.locator("#type-chart .chart__vehicles path, #type-chart .chart__vehicles circle")
    ).to_have_count(15)
    found["result"] = axe_violations(page, axe_script)
    if TAKE_SCREENSHOTS:
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SCREENSHOTS / "type-assessment-1280.png"), full_page=True)
        page.set_viewport_size({"width": 360, "height": 740})
        page.screenshot(path=str(SCREENSHOTS / "type-assessment-360.png"), full_page=True)
        page.set_viewport_size({"width": 1280, "height": 900})

    page.goto("/statistics")
    expect(page.locator("#per-model")).to_contain_text("Bajaj RE")
    found["statistics"] = axe_violations(page, axe_script)
    assert {name: v for name, v in found.items() if v} == {}, json.dumps(found, indent=1)
