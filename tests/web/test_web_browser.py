"""The officer pages in a real browser: Debian's Chromium driven by Playwright against the app
served by uvicorn. Sign in, register, inspect (valid and invalid), read Table 4 and the chart,
sign out and go back, CSRF refusal, a 360-px run, and axe-core on the main pages."""

from __future__ import annotations

import re
from collections.abc import Callable

import pytest
from playwright.sync_api import BrowserContext, Page, expect
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.inspections.models import Inspection
from app.vehicles.models import Vehicle
from web.webtools import OFFICER_EMAIL, PASSWORD, REPO

pytestmark = pytest.mark.browser

SCREENSHOTS = REPO / "docs" / "screenshots"


def sign_in(page: Page, email: str = OFFICER_EMAIL, password: str = PASSWORD) -> None:
    """Fill and send the sign-in form."""
    page.goto("/login")
    page.get_by_label("Email address").fill(email)
    page.get_by_label("Password").fill(password)
    page.get_by_role("button", name="Sign in").click()


def fill_study_readings(page: Page) -> None:
    """The study's readings: a = 108 (three times), b = 115, c = 135, W = 359."""
    for box in ("front_kg_1", "front_kg_2", "front_kg_3"):
        page.locator(f"#{box}").fill("108")
    page.locator("#left_rear_kg_1").fill("115")
    page.locator("#right_rear_kg_1").fill("135")
    page.locator("#overall_kg_1").fill("359")


def inspections(session: Session) -> int:
    session.expire_all()
    return session.scalar(select(func.count()).select_from(Inspection)) or 0


def test_sign_in_with_a_wrong_then_the_right_password(page: Page, officer: User) -> None:
    sign_in(page, password="not my password")
    summary = page.locator(".error-summary")
    expect(summary).to_contain_text("There is a problem")
    expect(summary.get_by_role("link")).to_have_text("Enter a correct email address and password")
    expect(page.get_by_label("Email address")).to_have_value(OFFICER_EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()
    expect(page).to_have_url("/")
    expect(page.get_by_role("heading", level=1)).to_have_text("Today’s inspections")
    expect(page.get_by_role("button", name="Sign out")).to_be_visible()


def test_register_a_vehicle_then_inspect_it_and_read_table_4_and_the_chart(
    page: Page, officer: User, session: Session
) -> None:
    sign_in(page)
    page.get_by_role("link", name="Register a vehicle").first.click()
    page.get_by_label("Registration number").fill("bdg-252 qh")
    page.get_by_label("Make").fill("Bajaj")
    page.get_by_label("Model", exact=True).fill("RE")
    page.get_by_label("Wheelbase (m)").fill("2.000")
    page.get_by_label("Driver’s seat (m)").fill("0.9303")
    for i in (1, 2, 3):
        page.get_by_label(f"Passenger seat {i} (m)").fill("1.6303")
    page.get_by_role("button", name="Register vehicle").click()
    expect(page).to_have_url("/vehicles/BDG252QH")
    expect(page.locator(".notification")).to_have_text("Vehicle BDG 252 QH registered.")

    page.get_by_role("link", name="Record an inspection").click()
    expect(page.get_by_label("Wheelbase (m)")).to_have_value("2.000")
    expect(page.get_by_label("Standard occupant mass (kg)")).to_have_value("72")
    fill_study_readings(page)
    page.get_by_role("button", name="Assess and save inspection").click()
    expect(page).to_have_url(re.compile(r"/inspections/\d+$"))

    rows = page.locator("#table-4 tbody tr")
    expect(rows).to_have_count(5)
    expect(rows.nth(0)).to_contain_text("Empty (no occupants)")
    expect(rows.nth(1)).to_contain_text("Driver")
    table = [[c.strip() for c in rows.nth(i).locator("th, td").all_inner_texts()] for i in range(5)]
    assert [row[-1].split()[0] for row in table] == ["NC", "C", "NC", "NC", "NC"]
    assert table[1][1:6] == ["431.00", "283.49", "0.658", "2/3 (0.667)", "+0.009"]
    expect(page.locator("#verdict")).to_contain_text(
        "Not compliant. Laterally stable with the driver alone; "
        "unstable with the driver and one or more passengers."
    )
    expect(page.locator("#occupancy")).to_have_text("This vehicle must not carry passengers")

    chart = page.locator("svg#lsf-chart")
    expect(chart).to_be_visible()
    expect(chart.locator("title")).to_have_text(
        "Lateral Stability Factor per loading case, against the 2/3 limit"
    )
    expect(chart.locator("desc")).to_contain_text("Driver: 0.658, C (compliant)")
    expect(chart.locator("circle.chart__c")).to_have_count(1)
    expect(chart.locator("path.chart__nc")).to_have_count(4)
    expect(chart.locator("text", has_text="limit 2/3")).to_be_visible()
    expect(chart.locator("text", has_text="unstable")).to_be_visible()
    assert inspections(session) == 1


def test_an_invalid_inspection_shows_the_message_beside_the_field_and_stores_nothing(
    page: Page, officer: User, study_vehicle: Vehicle, session: Session
) -> None:
    sign_in(page, OFFICER_EMAIL)
    page.goto("/vehicles/BDG252QH/inspections/new")
    fill_study_readings(page)
    page.locator("#overall_kg_1").fill("400")
    page.get_by_role("button", name="Assess and save inspection").click()
    message = "The three wheel readings add up to 358 kg but the overall weight is 400 kg"
    link = page.locator(".error-summary").get_by_role("link")
    expect(link).to_contain_text(message)
    expect(page.locator("#overall_kg_1-error")).to_contain_text(message)
    expect(page.locator("#overall_kg_1")).to_have_value("400")
    expect(page.locator("#front_kg_2")).to_have_value("108")
    link.click()
    expect(page.locator("#overall_kg_1")).to_be_focused()
    assert inspections(session) == 0


def test_signing_out_ends_the_session_and_back_shows_no_protected_content(
    page: Page, officer: User, study_vehicle: Vehicle
) -> None:
    sign_in(page)
    page.goto("/vehicles/BDG252QH")
    expect(page.get_by_role("heading", level=1)).to_have_text("BDG 252 QH")
    page.get_by_role("button", name="Sign out").click()
    expect(page).to_have_url("/login?signed_out=1")
    expect(page.get_by_role("status")).to_have_text("You have signed out.")
    page.go_back()
    page.wait_for_load_state()
    assert "BDG 252 QH" not in page.content()
    expect(page.get_by_role("heading", level=1)).to_have_text("Sign in")
    page.goto("/vehicles/BDG252QH")
    expect(page.get_by_role("heading", level=1)).to_have_text("Sign in")


def test_a_form_whose_csrf_token_was_tampered_with_is_refused(
    page: Page, officer: User, session: Session
) -> None:
    sign_in(page)
    page.goto("/vehicles/new")
    page.locator("form:has(#registration_number) input[name=csrf_token]").evaluate("e => e.value = 'forged'")
    page.get_by_label("Registration number").fill("KJA 1 AB")
    page.get_by_label("Make").fill("Bajaj")
    page.get_by_label("Model", exact=True).fill("RE")
    page.get_by_label("Wheelbase (m)").fill("2")
    page.get_by_label("Driver’s seat (m)").fill("0.93")
    with page.expect_response(lambda r: r.request.method == "POST") as answer:
        page.get_by_role("button", name="Register vehicle").click()
    assert answer.value.status == 403
    expect(page.get_by_role("heading", level=1)).to_have_text("Sorry, you will have to start again")
    session.expire_all()
    assert session.scalar(select(func.count()).select_from(Vehicle)) == 0


def test_the_skip_link_is_the_first_stop_for_the_keyboard(page: Page, officer: User) -> None:
    sign_in(page)
    expect(page).to_have_url("/")
    page.goto("/vehicles/find")  # a fresh load: the keyboard starts at the top of the document
    expect(page.get_by_role("heading", level=1)).to_have_text("Find a vehicle")
    page.keyboard.press("Tab")
    skip = page.get_by_role("link", name="Skip to main content")
    expect(skip).to_be_focused()
    expect(skip).to_be_visible()
    page.keyboard.press("Enter")
    expect(page).to_have_url("/vehicles/find#main")


@pytest.fixture
def narrow_page(kept_context: Callable[..., BrowserContext]) -> Page:
    """A phone-sized page, 360 px wide, with JavaScript switched off: every page must work without it."""
    return kept_context(viewport={"width": 360, "height": 740}, java_script_enabled=False).new_page()


def no_sideways_scroll(page: Page, url: str | re.Pattern[str]) -> None:
    """Once the page at `url` has loaded (a click only starts its navigation), it is no wider than 360 px."""
    expect(page).to_have_url(url)
    page.wait_for_load_state()
    width = page.evaluate("document.documentElement.scrollWidth")
    assert width <= 360, f"{page.url} is {width} px wide"


def test_the_whole_job_works_at_360_px_without_javascript(
    narrow_page: Page, officer: User, study_vehicle: Vehicle
) -> None:
    page = narrow_page
    sign_in(page)
    no_sideways_scroll(page, "/")
    page.get_by_role("link", name="Find a vehicle").first.click()
    page.get_by_label("Registration number").fill("bdg 252qh")
    page.get_by_role("button", name="Find vehicle").click()
    no_sideways_scroll(page, "/vehicles/BDG252QH")
    page.get_by_role("link", name="Record an inspection").click()
    no_sideways_scroll(page, "/vehicles/BDG252QH/inspections/new")
    fill_study_readings(page)
    page.get_by_role("button", name="Assess and save inspection").click()
    expect(page.locator("#occupancy")).to_have_text("This vehicle must not carry passengers")
    no_sideways_scroll(page, re.compile(r"/inspections/\d+$"))
    box = page.locator("svg#lsf-chart").bounding_box()
    assert box is not None
    assert box["width"] <= 360
    for url in ("/inspections", "/vehicles/new", "/"):
        page.goto(url)
        no_sideways_scroll(page, url)
