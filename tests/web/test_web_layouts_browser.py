"""An officer registers a tadpole and a quadricycle in Debian's Chromium, enters their readings and issues
their documents: each page and paper shows the layout's wheels and limit. With TRIKECERT_SCREENSHOTS=1
the pages are saved at 360 and 1280 px as docs/screenshots/layout-*.png, and each PDF's first page."""

from __future__ import annotations

import io
import re

import pypdfium2  # type: ignore[import-untyped]
import pytest
from playwright.sync_api import Page, expect
from pypdf import PdfReader

from app.accounts.models import User
from web.webtools import OFFICER_EMAIL, PASSWORD, SCREENSHOTS, TAKE_SCREENSHOTS

pytestmark = pytest.mark.browser

TADPOLE_SEATS = ("0.700", "1.350", "1.350", "1.350")
QUADRICYCLE_SEATS = ("0.900", "1.000")


def sign_in(page: Page) -> None:
    page.goto("/login")
    page.get_by_label("Email address").fill(OFFICER_EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()
    expect(page.get_by_role("navigation", name="Main")).to_be_visible()


def shoot(page: Page, name: str) -> None:
    """The open page, whole, at 1280 px and at 360 px (only with TRIKECERT_SCREENSHOTS=1)."""
    if not TAKE_SCREENSHOTS:
        return
    for width in (1280, 360):
        page.set_viewport_size({"width": width, "height": 900})
        page.screenshot(path=str(SCREENSHOTS / f"layout-{name}-{width}.png"), full_page=True)
    page.set_viewport_size({"width": 1280, "height": 900})


def register(page: Page, plate: str, layout: str, wheelbase: str, seats: tuple[str, ...]) -> None:
    page.goto("/vehicles/new")
    page.get_by_label("Registration number").fill(plate)
    page.get_by_label(layout).check()
    page.get_by_label("Make").fill("Example")
    page.get_by_label("Model", exact=True).fill("E-" + layout.split(" ")[0])
    page.get_by_label("Wheelbase (m)").fill(wheelbase)
    page.get_by_label("Driver’s seat (m)").fill(seats[0])
    for i, x in enumerate(seats[1:], start=1):
        page.get_by_label(f"Passenger seat {i} (m)").fill(x)
    page.get_by_role("button", name="Register vehicle").click()
    expect(page.get_by_role("heading", level=1)).to_have_text(plate)
    expect(page.locator(".summary-list").first).to_contain_text(layout)


def record(page: Page, readings: dict[str, str]) -> None:
    page.get_by_role("link", name="Record an inspection").click()
    for box, value in readings.items():
        page.locator(f"#{box}").fill(value)
    page.get_by_role("button", name="Assess and save inspection").click()
    expect(page.locator("#table-4")).to_be_visible()


def issue(page: Page, kind: str, name: str) -> str:
    """Issue the inspection's document from its page; the PDF's text."""
    page.get_by_role("button", name=f"Issue the {kind}").click()
    expect(page).to_have_url(re.compile(r"/certificates/[^/]+$"))
    number = page.url.rsplit("/", 1)[-1]
    response = page.request.get(f"/certificates/{number}/pdf")
    assert response.ok
    pdf = response.body()
    if TAKE_SCREENSHOTS:
        document = pypdfium2.PdfDocument(pdf)
        try:
            document[0].render(scale=110 / 72).to_pil().save(SCREENSHOTS / f"layout-{name}-pdf.png")
        finally:
            document.close()
    return " ".join(" ".join(p.extract_text().split()) for p in PdfReader(io.BytesIO(pdf)).pages)


def test_an_officer_registers_weighs_and_certifies_a_tadpole_and_a_quadricycle(
    page: Page, officer: User
) -> None:
    sign_in(page)
    page.goto("/vehicles/new")
    expect(page.get_by_label("Delta (one front wheel and two rear wheels): limit 2/3")).to_be_checked()
    shoot(page, "register")

    register(page, "TDP 101 EV", "Tadpole (two front wheels and one rear wheel)", "1.900", TADPOLE_SEATS)
    page.get_by_role("link", name="Record an inspection").click()
    for label in (
        "Left front wheel reaction (kg)",
        "Right front wheel reaction (kg)",
        "Rear wheel reaction (kg)",
    ):
        expect(page.get_by_role("group", name=label)).to_be_visible()
    expect(page.get_by_role("group", name="Front wheel reaction (kg)", exact=True)).to_have_count(0)
    shoot(page, "tadpole-readings")
    page.go_back()
    record(
        page, {"left_front_kg_1": "186", "right_front_kg_1": "182", "rear_kg_1": "112", "overall_kg_1": "480"}
    )
    table = page.locator("#table-4")
    expect(table).to_contain_text("Weight on the rear wheel (kg)")
    expect(table).to_contain_text("1/3 (0.333)")
    rows = table.locator("tbody tr")
    expect(rows).to_have_count(5)
    expect(rows.nth(3)).to_contain_text("0.346")
    expect(rows.nth(3)).to_contain_text("NC")
    expect(page.locator("#occupancy")).to_have_text(
        "This vehicle may carry the driver and up to one passenger, no more"
    )
    expect(page.locator("#lsf-chart")).to_contain_text("limit 1/3")
    shoot(page, "tadpole-inspection")
    text = issue(page, "refusal", "tadpole-refusal")
    assert "Weight on the rear wheel (kg)" in text
    assert "1/3 (0.333)" in text
    assert "2/3" not in text
    expect(page.locator("#table-4")).to_contain_text("Weight on the rear wheel (kg)")
    expect(page.locator("#table-4")).to_contain_text("1/3 (0.333)")
    shoot(page, "tadpole-refusal")

    register(
        page, "QDC 202 AA", "Quadricycle (two front wheels and two rear wheels)", "2.000", QUADRICYCLE_SEATS
    )
    record(
        page,
        {
            "left_front_kg_1": "150",
            "left_front_kg_2": "152",
            "right_front_kg_1": "148",
            "left_rear_kg_1": "140",
            "right_rear_kg_1": "143",
            "overall_kg_1": "582",
        },
    )
    table = page.locator("#table-4")
    expect(table).to_contain_text("Weight on rear wheels (kg)")
    expect(table).to_contain_text("1/2 (0.500)")
    expect(page.locator("#occupancy")).to_have_text("Certified for the driver and up to one passenger")
    expect(page.locator("#lsf-chart")).to_contain_text("limit 1/2")
    shoot(page, "quadricycle-inspection")
    text = issue(page, "certificate", "quadricycle-certificate")
    assert "1/2 (0.500)" in text
    assert "Left front wheel: 151" in text
    assert "Right rear wheel: 143" in text
    expect(page.locator("#table-4")).to_contain_text("1/2 (0.500)")
    shoot(page, "quadricycle-certificate")
