"""Beyond the static test in a real browser, as a new officer would: give the study vehicle the
reference's illustrative figures, weigh it with the front wheel raised, and read the estimates and the
stability map; axe-core finds nothing on the figures form or the result. With TRIKECERT_SCREENSHOTS=1
the estimates section is saved as docs/screenshots/dynamics-1280.png and dynamics-360.png."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from playwright.sync_api import Page, expect

from app.accounts.models import User
from app.vehicles.models import Vehicle
from web.test_web_browser import fill_study_readings, sign_in
from web.webtools import REPO, axe_violations

pytestmark = pytest.mark.browser

SCREENSHOTS = REPO / "docs" / "screenshots"
FIGURES = {
    "#track_m": "1.150",
    "#wheel_radius_m": "0.190",
    "#seat_z_m_0": "0.75",
    "#seat_z_m_1": "0.80",
    "#seat_z_m_2": "0.80",
    "#seat_z_m_3": "0.80",
    "#front_cornering_stiffness_n_per_rad": "8000",
    "#rear_cornering_stiffness_n_per_rad": "8000",
    "#drag_area_m2": "1.6",
    "#centre_of_pressure_height_m": "0.900",
}


def test_an_officer_reads_the_rollover_estimates_and_the_stability_map(
    audit_page: Page, axe_script: Path, officer: User, study_vehicle: Vehicle
) -> None:
    page = audit_page
    sign_in(page)
    page.goto("/vehicles/BDG252QH")
    page.get_by_role("link", name="Change the figures for the estimates").click()
    assert axe_violations(page, axe_script) == []
    for box, value in FIGURES.items():
        page.locator(box).fill(value)
    page.get_by_role("button", name="Record the figures").click()
    expect(page.locator("#vehicle-figures")).to_contain_text("1.15")

    page.get_by_role("link", name="Record an inspection").click()
    fill_study_readings(page)
    page.get_by_text("Centre of gravity height by raising the front wheel (optional)").click()
    page.get_by_label("Front wheel raised by (m)").fill("0.40")
    page.locator("#cg_front_kg_1").fill("94.8")
    page.get_by_role("button", name="Assess and save inspection").click()

    section = page.locator("#estimates")
    expect(
        section.get_by_role("heading", name="Beyond the static test (estimates, not part of the verdict)")
    ).to_be_visible()
    table = page.locator("#estimates-table")
    for figure in ("0.5503 m", "0.7277 g", "36.04°", "113.8 km/h", "None (understeers)", "70.0 km/h"):
        expect(table).to_contain_text(figure)
    expect(page.locator("#estimates-inputs")).to_contain_text("94.8 kg")
    expect(page.locator("#stability-map .chart__point")).to_have_count(5)
    expect(page.locator("#table-4")).to_contain_text("C Compliant")  # the static verdict is unchanged
    assert axe_violations(page, axe_script) == []
    if os.environ.get("TRIKECERT_SCREENSHOTS") == "1":
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        section.screenshot(path=str(SCREENSHOTS / "dynamics-1280.png"))
        page.set_viewport_size({"width": 360, "height": 740})
        section.screenshot(path=str(SCREENSHOTS / "dynamics-360.png"))
