"""Every page on a 360 px phone, in Debian's Chromium: no element is wider than the screen (officer,
administrator and public pages, each with records that fill its tables), the charts' labels are big
enough to read and the stability map's labels do not overlap (read from the SVG's geometry). With
TRIKECERT_SCREENSHOTS=1 the pages this walk is the only one to show are saved at 360 px."""

from __future__ import annotations

import json
from dataclasses import dataclass
from datetime import date
from decimal import Decimal
from typing import Any

import pyotp
import pytest
from playwright.sync_api import Page, expect
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, revoke_certificate
from app.config import get_settings
from app.dynamics.estimates import CgLift
from app.dynamics.service import DynamicsFigures, record_figures
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import WheelReadings
from app.stations.details import StationDetails
from app.stations.service import create_station
from app.type_assessments.service import TypeRequest, create_type_assessment
from app.vehicles.models import Vehicle
from app.vehicles.service import register_vehicle
from web.webtools import (
    ADMIN_EMAIL,
    PASSWORD,
    SCREENSHOTS,
    STUDY_SEATS,
    TAKE_SCREENSHOTS,
    weigh_study_fleet,
    wheel_readings,
)

pytestmark = pytest.mark.browser

WIDTH = 360


@dataclass(frozen=True)
class Records:
    """What the walk's pages show."""

    refused_inspection: int  # the study's weighing, older than a certified one of the same vehicle
    certified_inspection: int
    certificate: str
    revoked: str
    refusal: str
    type_assessment: int
    station: int
    officer: int


@pytest.fixture
def records(session: Session, admin: User, officer: User, study_vehicle: Vehicle) -> Records:
    """The study's vehicle weighed twice (refused, then certified after a change), with the
    reference's figures for the estimates; a vehicle with a long plate, certified then revoked; one
    refused; the study's fleet assessed as a type; a station with a long name."""
    settings, rules = get_settings(), get_settings().rules()
    station, _key = create_station(
        session,
        name="Lagos-Badagry Expressway weighbridge (Agbara)",
        details=StationDetails(
            location="Lagos-Badagry Expressway, Agbara, Ogun State",
            calibration_certificate="SON/CAL/2026/0415",
            calibration_valid_until=date(2099, 3, 31),
            capacity_kg=Decimal(3000),
            division_kg=Decimal(1),
        ),
    )
    record_figures(
        session,
        study_vehicle,
        DynamicsFigures(
            track_m=Decimal("1.150"),
            wheel_radius_m=Decimal("0.190"),
            seat_heights_m=(Decimal("0.75"), Decimal("0.80"), Decimal("0.80"), Decimal("0.80")),
            front_cornering_stiffness_n_per_rad=Decimal(8000),
            rear_cornering_stiffness_n_per_rad=Decimal(8000),
            drag_area_m2=Decimal("1.6"),
            centre_of_pressure_height_m=Decimal("0.900"),
        ),
    )
    lift = CgLift(lift_height_m=Decimal("0.40"), front_kg=(Decimal("94.8"),))

    def weigh(plate: str, wheels: WheelReadings, *, with_lift: bool = False) -> int:
        request = InspectionRequest(
            registration_number=plate, readings=wheels, cg_lift=lift if with_lift else None
        )
        return record_inspection(session, request=request, rules=rules, station=station).id

    refused = weigh("BDG 252 QH", wheel_readings(108, 115, 135, 359), with_lift=True)
    certified = weigh("BDG 252 QH", wheel_readings(200, 80, 80, 360), with_lift=True)
    actor = Actor.of_user(admin)
    certificate = issue_certificate(session, inspection_id=certified, actor=actor, settings=settings)
    for plate in ("LAG 888 YB", "KTU 123 XA"):
        register_vehicle(
            session,
            registration_number=plate,
            make="TVS",
            model="King Deluxe 4-stroke",
            model_year=2019,
            chassis_number="MD6M14PA9K4A12345",
            wheelbase_m=Decimal("2.000"),
            seats=STUDY_SEATS,
        )
    revoked = issue_certificate(
        session,
        inspection_id=weigh("LAG 888 YB", wheel_readings(200, 80, 80, 360)),
        actor=actor,
        settings=settings,
    ).certificate.number
    revoke_certificate(session, number=revoked, actor=actor, reason="Wrong wheel readings entered")
    refusal = issue_certificate(
        session,
        inspection_id=weigh("KTU 123 XA", wheel_readings(100, 120, 140, 360)),
        actor=actor,
        settings=settings,
    ).certificate.number
    weigh_study_fleet(session, model="RE 2-stroke", suffix="9")
    assessment = create_type_assessment(
        session, request=TypeRequest(make="Bajaj", model="RE 2-stroke"), rules=rules, user_id=admin.id
    )
    return Records(
        refused_inspection=refused,
        certified_inspection=certified,
        certificate=certificate.certificate.number,
        revoked=revoked,
        refusal=refusal,
        type_assessment=assessment.id,
        station=station.id,
        officer=officer.id,
    )


def pages(r: Records) -> list[str]:
    """Every page an officer, an administrator or the public opens, with records in it."""
    return [
        "/",
        "/vehicles/find",
        "/vehicles/find?registration=LAG",
        "/vehicles/new",
        "/vehicles/BDG252QH",
        "/vehicles/LAG888YB",
        "/vehicles/KTU123XA",
        "/vehicles/BDG252QH/dynamics",
        "/vehicles/BDG252QH/inspections/new",
        f"/inspections/{r.refused_inspection}",
        f"/inspections/{r.certified_inspection}",
        "/inspections",
        f"/certificates/{r.certificate}",
        f"/certificates/{r.revoked}",
        f"/certificates/{r.refusal}",
        "/statistics",
        "/type-assessments/new?make=Bajaj&model=RE+2-stroke",
        f"/type-assessments/{r.type_assessment}",
        "/admin/users",
        "/admin/users/new",
        f"/admin/users/{r.officer}/edit",
        f"/admin/users/{r.officer}/password",
        "/admin/stations",
        "/admin/stations/new",
        f"/admin/stations/{r.station}",
        "/admin/settings",
        "/admin/audit",
        "/verify",
        f"/verify/{r.certificate}",
        f"/verify/{r.revoked}",
        f"/verify/{r.refusal}",
        "/verify/TRK-2026-999999-A",
    ]


WIDER_THAN_THE_SCREEN = """(width) => {
  const found = [];
  for (const element of document.querySelectorAll("body *")) {
    const box = element.getBoundingClientRect();
    // Hidden until focused (the skip link): wholly off the screen, not sticking out of it.
    if (box.width === 0 || box.right <= 0 || getComputedStyle(element).visibility === "hidden") continue;
    if (box.left < -0.5 || box.right > width + 0.5) {
      const text = (element.textContent || "").trim().replace(/\\s+/g, " ").slice(0, 40);
      found.push(`${element.tagName.toLowerCase()}.${element.className.baseVal ?? element.className}`
        + ` ${Math.round(box.left)}..${Math.round(box.right)} px: ${text}`);
    }
  }
  return {found, scroll: document.documentElement.scrollWidth};
}"""


SPLIT_OVER_TWO_LINES = """() => {
  const kept = /BDG 252 QH9?|LAG 888 YB|KTU 123 XA|\\d+(?:\\.\\d+)?[ \\u00a0]%/g;
  const found = [];
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let node = walker.nextNode(); node; node = walker.nextNode()) {
    for (const match of node.data.matchAll(kept)) {
      const range = document.createRange();
      range.setStart(node, match.index);
      range.setEnd(node, match.index + match[0].length);
      const boxes = [...range.getClientRects()].filter((r) => r.width > 0);
      const tops = new Set(boxes.map((r) => Math.round(r.top)));
      if (tops.size > 1) found.push(`"${match[0]}" split over ${tops.size} lines`);
    }
  }
  return found;
}"""


def sign_in(page: Page) -> None:
    page.goto("/login")
    page.get_by_label("Email address").fill(ADMIN_EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()
    expect(page.get_by_role("navigation", name="Main")).to_be_visible()


def wider(page: Page) -> list[str]:
    """What sticks out of a 360 px screen on the open page."""
    result: dict[str, Any] = page.evaluate(WIDER_THAN_THE_SCREEN, WIDTH)
    found: list[str] = result["found"]
    if result["scroll"] > WIDTH:
        found.append(f"the page scrolls sideways: {result['scroll']} px")
    split: list[str] = page.evaluate(SPLIT_OVER_TWO_LINES)
    return found + split


def test_no_page_is_wider_than_a_360_px_phone_nor_splits_a_plate_or_a_percentage(
    page: Page, records: Records
) -> None:
    page.set_viewport_size({"width": WIDTH, "height": 740})
    page.goto("/login")
    found = {"/login": wider(page)}
    sign_in(page)
    for url in pages(records):
        answer = page.goto(url)
        assert answer is not None
        assert answer.status == (404 if "999999" in url else 200), url
        found[url] = wider(page)
    page.goto("/vehicles/BDG252QH/inspections/new")
    for box, value in (("front", "108"), ("left_rear", "115"), ("right_rear", "135"), ("overall", "400")):
        page.locator(f"#{box}_kg_1").fill(value)
    page.get_by_role("button", name="Assess and save inspection").click()
    expect(page.locator(".error-summary")).to_contain_text("10.5")
    found["the inspection form's errors"] = wider(page)
    page.goto("/account/two-factor")
    found["/account/two-factor"] = wider(page)
    page.get_by_label("Code from the app").fill(pyotp.TOTP(page.locator("#secret").inner_text()).now())
    page.get_by_role("button", name="Confirm and turn on").click()
    expect(page.get_by_role("heading", level=1)).to_have_text("Your recovery codes")
    found["the recovery codes"] = wider(page)
    wide = {url: items for url, items in found.items() if items}
    assert wide == {}, json.dumps(wide, indent=1)


LABELS_OF = """(selector) => [...document.querySelectorAll(selector + " text")].map((t) => {
  const b = t.getBoundingClientRect();
  return {text: t.textContent.trim(), size: parseFloat(getComputedStyle(t).fontSize)
    * (t.ownerSVGElement.getBoundingClientRect().width / t.ownerSVGElement.viewBox.baseVal.width),
    left: b.left, right: b.right, top: b.top, bottom: b.bottom};
})"""

LINES_OF = """(selector) => [...document.querySelectorAll(selector + " line, " + selector + " path")]
  .filter((l) => l.classList.length).map((l) => {
  const b = l.getBoundingClientRect();
  return {cls: l.getAttribute("class"), left: b.left, right: b.right, top: b.top, bottom: b.bottom};
})"""


def overlap(a: dict[str, float], b: dict[str, float]) -> bool:
    """Whether two boxes share any area."""
    return (
        a["left"] < b["right"]
        and b["left"] < a["right"]
        and a["top"] < b["bottom"]
        and b["top"] < a["bottom"]
    )


@pytest.mark.parametrize("width", [WIDTH, 1280])
def test_the_charts_labels_are_readable_and_the_maps_do_not_overlap(
    page: Page, records: Records, width: int
) -> None:
    page.set_viewport_size({"width": width, "height": 900})
    sign_in(page)
    page.goto(f"/inspections/{records.refused_inspection}")
    for chart in ("#lsf-chart", "#stability-map"):
        labels = page.evaluate(LABELS_OF, chart)
        assert len(labels) >= 5, chart
        small = [(label["text"], round(label["size"], 1)) for label in labels if label["size"] < 11]
        assert small == [], f"{chart} at {width} px: labels under 11 px"
    labels = page.evaluate(LABELS_OF, "#stability-map")
    crossing = [
        (a["text"], b["text"]) for i, a in enumerate(labels) for b in labels[i + 1 :] if overlap(a, b)
    ]
    assert crossing == [], f"stability map at {width} px: labels overlap"
    limit = page.locator("#stability-map .chart__limit").first.bounding_box()
    assert limit is not None
    points = [label for label in labels if label["text"] in ("Empty", "Driver", "+1", "+2", "+3")]
    assert len(points) == 5
    across = [p["text"] for p in points if p["left"] < limit["x"] + limit["width"] / 2 < p["right"]]
    assert across == [], f"stability map at {width} px: point labels cross the 2/3 line"
    if TAKE_SCREENSHOTS and width == WIDTH:
        page.locator("#estimates").screenshot(path=str(SCREENSHOTS / "dynamics-360.png"))
