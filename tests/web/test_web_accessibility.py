"""axe-core (from the npm registry, `npm ci` at the top of the repository) finds no violation on the
main pages; with TRIKECERT_SCREENSHOTS=1 the same run saves them at 1280 and 360 px in docs/screenshots/."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Page, expect
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.config import get_settings
from app.inspections.models import Inspection
from app.inspections.service import InspectionRequest, record_inspection
from app.vehicles.models import Vehicle
from web.webtools import ADMIN_EMAIL, PASSWORD, SCREENSHOTS, TAKE_SCREENSHOTS, axe_violations, wheel_readings

pytestmark = pytest.mark.browser


@pytest.fixture
def study_inspection(session: Session, study_vehicle: Vehicle, admin: User) -> Inspection:
    """The study's inspection of BDG 252 QH, recorded by the admin."""
    readings = wheel_readings(108, 115, 135, 359)
    return record_inspection(
        session,
        request=InspectionRequest(registration_number="BDG252QH", readings=readings),
        rules=get_settings().rules(),
        user_id=admin.id,
    )


def submit_invalid_inspection(page: Page) -> None:
    page.locator("#front_kg_1").fill("1O8")
    page.locator("#overall_kg_1").fill("359")
    page.get_by_role("button", name="Assess and save inspection").click()
    expect(page.locator(".error-summary")).to_be_visible()


def submit_invalid_vehicle(page: Page) -> None:
    page.get_by_role("button", name="Register vehicle").click()
    expect(page.locator(".error-summary")).to_be_visible()


def submit_invalid_station(page: Page) -> None:
    page.locator("#capacity_kg").fill("three tonnes")
    page.locator("#valid_until_day").fill("31")
    page.get_by_role("button", name="Add station").click()
    expect(page.locator(".error-summary")).to_be_visible()


def add_station(page: Page) -> None:
    page.locator("#name").fill("Agbara weighbridge")
    page.locator("#location").fill("Lagos-Badagry Expressway, Agbara")
    page.locator("#calibration_certificate").fill("SON/CAL/2026/0415")
    page.locator("#valid_until_day").fill("31")
    page.locator("#valid_until_month").fill("3")
    page.locator("#valid_until_year").fill("2027")
    page.locator("#capacity_kg").fill("3000")
    page.locator("#division_kg").fill("1")
    page.get_by_role("button", name="Add station").click()
    expect(page.locator("#station-key")).to_be_visible()


def open_station(page: Page) -> None:
    page.get_by_role("link", name="Agbara weighbridge").click()
    expect(page.get_by_role("heading", name="Agbara weighbridge")).to_be_visible()


def submit_invalid_station_edit(page: Page) -> None:
    open_station(page)
    page.locator("#name").fill("")
    page.locator("#division_kg").fill("5000")
    page.get_by_role("button", name="Save details").click()
    expect(page.locator(".error-summary")).to_be_visible()


MAIN_PAGES: list[tuple[str, str, Callable[[Page], None] | None]] = [
    ("login", "/login", None),
    ("home", "/", None),
    ("find-vehicle", "/vehicles/find", None),
    ("register-vehicle", "/vehicles/new", None),
    ("register-vehicle-errors", "/vehicles/new", submit_invalid_vehicle),
    ("vehicle", "/vehicles/BDG252QH", None),
    ("new-inspection", "/vehicles/BDG252QH/inspections/new", None),
    ("new-inspection-errors", "/vehicles/BDG252QH/inspections/new", submit_invalid_inspection),
    ("inspection", "/inspections/{id}", None),
    ("inspections", "/inspections", None),
    ("statistics", "/statistics", None),
    ("users", "/admin/users", None),
    ("new-station", "/admin/stations/new", None),
    ("new-station-errors", "/admin/stations/new", submit_invalid_station),
    ("station-key", "/admin/stations/new", add_station),
    ("stations", "/admin/stations", None),
    ("station", "/admin/stations", open_station),
    ("station-errors", "/admin/stations", submit_invalid_station_edit),
    ("settings", "/admin/settings", None),
    ("audit", "/admin/audit?actor_kind=anonymous&action=sign_in.&from=2026-01-01", None),
    ("audit-errors", "/admin/audit?action=sign_in&from=23/11/2026", None),
]


def test_the_main_pages_have_no_axe_violations(
    audit_page: Page, axe_script: Path, study_inspection: Inspection
) -> None:
    page = audit_page
    found: dict[str, list[dict[str, Any]]] = {}
    for name, url, action in MAIN_PAGES:
        if name == "home":
            page.get_by_label("Email address").fill(ADMIN_EMAIL)
            page.get_by_label("Password").fill(PASSWORD)
            page.get_by_role("button", name="Sign in").click()
        else:
            page.goto(url.format(id=study_inspection.id))
        if action is not None:
            action(page)
        if violations := axe_violations(page, axe_script):
            found[name] = violations
        if TAKE_SCREENSHOTS:
            SCREENSHOTS.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(SCREENSHOTS / f"{name}-1280.png"), full_page=True)
            page.set_viewport_size({"width": 360, "height": 740})
            page.screenshot(path=str(SCREENSHOTS / f"{name}-360.png"), full_page=True)
            page.set_viewport_size({"width": 1280, "height": 900})
    assert found == {}, json.dumps(found, indent=1)
