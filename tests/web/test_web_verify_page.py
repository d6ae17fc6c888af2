"""The public verify page in the real browser at 360 and 1280 px: one banner says what the paper means.

A certificate in force, a refusal, a revoked, a superseded and an expired document and a tampered QR
payload each show their banner (words and colour) within the first 640 px of a phone's screen. The
QR check's colour follows the document, not the signature (issue 21): green only under a certificate
in force, never under a red or grey banner; an unknown or mistyped number gets a red banner with the
form's words. With TRIKECERT_SCREENSHOTS=1 the run saves them as
docs/screenshots/verify-<state>-<width>.png.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from datetime import timedelta
from pathlib import Path
from typing import Any
from urllib.parse import quote

import pytest
from fastapi.testclient import TestClient
from playwright.sync_api import BrowserContext, Page, expect
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, revoke_certificate
from app.config import get_settings
from app.db import utcnow
from app.trust.numbers import check_letter
from web.webtools import REPO, axe_violations

pytestmark = pytest.mark.browser

SCREENSHOTS = REPO / "docs" / "screenshots"
TAKE_SCREENSHOTS = os.environ.get("TRIKECERT_SCREENSHOTS") == "1"
FOLD_PX = 640
GREEN, RED, GREY = "rgb(0, 112, 60)", "rgb(177, 14, 30)", "rgb(80, 90, 95)"
PALE_GREEN = "rgb(230, 243, 236)"  # the background of a green box
# A front-heavy trike of our own with two passenger seats: every loading case complies.
FRONT_HEAVY: dict[str, Any] = {
    "make": "TVS",
    "model": "King",
    "model_year": 2021,
    "chassis_number": "MD6M14PA7L4F00123",
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}] + [{"role": "passenger", "x_m": 1.4}] * 2,
}
FRONT_HEAVY_READINGS: dict[str, Any] = {"front_kg": 220, "left_rear_kg": 70, "right_rear_kg": 70}


def certify(api: TestClient, vehicle: dict[str, Any], readings: dict[str, Any]) -> dict[str, Any]:
    """Weigh a registered vehicle through the station API and return its certificate's JSON."""
    weighed = api.post(
        "/api/v1/inspections",
        json={"registration_number": vehicle["registration_number"], "readings": readings},
    )
    assert weighed.status_code == 201, weighed.text
    issued = api.post(f"/api/v1/inspections/{weighed.json()['id']}/certificate")
    assert issued.status_code == 201, issued.text
    body: dict[str, Any] = issued.json()
    return body


@pytest.fixture
def documents(api: TestClient, session: Session, backdate: Callable[..., None]) -> dict[str, dict[str, Any]]:
    """One document of every kind the banner tells apart, each with the path its QR code opens."""
    vehicles = {
        "certified": {**FRONT_HEAVY, "registration_number": "KTU-417-XA"},
        "revoked": {**FRONT_HEAVY, "registration_number": "LSR-902-AB"},
        "expired": {**FRONT_HEAVY, "registration_number": "EKY-311-CD"},
    }
    for vehicle in (STUDY_VEHICLE, *vehicles.values()):
        assert api.post("/api/v1/vehicles", json=vehicle).status_code == 201
    superseded = certify(api, vehicles["certified"], FRONT_HEAVY_READINGS)
    certified = certify(api, vehicles["certified"], FRONT_HEAVY_READINGS)
    revoked = certify(api, vehicles["revoked"], FRONT_HEAVY_READINGS)
    revoke_certificate(
        session, number=revoked["number"], actor=Actor.of_cli(), reason="Weighbridge ticket forged"
    )
    refusal = certify(api, STUDY_VEHICLE, STUDY_READINGS)
    weighed = api.post(
        "/api/v1/inspections",
        json={"registration_number": "EKY-311-CD", "readings": FRONT_HEAVY_READINGS},
    )
    long_ago = utcnow() - timedelta(days=400)
    backdate(weighed.json()["id"], long_ago - timedelta(hours=1))  # weighed, then issued, 400 days ago
    old = issue_certificate(
        session,
        inspection_id=weighed.json()["id"],
        actor=Actor.of_cli(),
        settings=get_settings(),
        now=long_ago,
    ).certificate
    expired = api.get(f"/api/v1/certificates/{old.number}").json()
    return {
        "certified": certified,
        "refusal": refusal,
        "revoked": revoked,
        "superseded": superseded,
        "expired": expired,
    }


def path_of(url: str) -> str:
    """A verify URL as a path on the live server."""
    return "/" + url.split("://", 1)[1].split("/", 1)[1]


def within_fold(page: Page, selector: str) -> None:
    """The element's bottom edge lies within the first 640 px of the page."""
    box = page.locator(selector).bounding_box()
    assert box is not None, selector
    assert box["y"] + box["height"] <= FOLD_PX, (selector, box)


def banner_colour(page: Page) -> str:
    colour: str = page.locator("#headline").evaluate("e => getComputedStyle(e).backgroundColor")
    return colour


CASES = [
    # state, headline (start), tone class, banner colour, occupancy or status line, QR box, QR title
    (
        "certified",
        "VALID CERTIFICATE",
        "status--valid",
        GREEN,
        "Certified for the driver and up to 2 passengers",
        "qr-check--genuine",
        "The QR code is genuine",
    ),
    (
        "refusal",
        "NOT CERTIFIED: refusal",
        "status--refused",
        RED,
        "This vehicle must not carry passengers",
        "qr-check--refused",
        "The QR code is genuine, but this paper is a REFUSAL",
    ),
    (
        "revoked",
        "REVOKED on ",
        "status--revoked",
        RED,
        "This certificate was withdrawn: it certifies nothing.",
        "qr-check--revoked",
        "The QR code is genuine, but this certificate was REVOKED",
    ),
    (
        "superseded",
        "SUPERSEDED on ",
        "status--lapsed",
        GREY,
        "This certificate was replaced and no longer counts.",
        "qr-check--lapsed",
        "The QR code is genuine, but this certificate was SUPERSEDED",
    ),
    (
        "expired",
        "EXPIRED on ",
        "status--lapsed",
        GREY,
        "This certificate no longer counts: the vehicle must be weighed again.",
        "qr-check--lapsed",
        "The QR code is genuine, but this certificate has EXPIRED",
    ),
]


def style(page: Page, selector: str, prop: str) -> str:
    """A computed style of the first element the selector finds."""
    value: str = page.locator(selector).first.evaluate(f"e => getComputedStyle(e).{prop}")
    return value


@pytest.mark.parametrize("width", [360, 1280])
def test_each_banner_says_what_the_paper_means_above_the_fold(
    page: Page, documents: dict[str, dict[str, Any]], width: int
) -> None:
    page.set_viewport_size({"width": width, "height": 740 if width == 360 else 900})
    for name, headline, tone, colour, line, qr_class, qr_title in CASES:
        document = documents[name]
        page.goto(path_of(document["qr_url"]))
        banner = page.locator("#status")
        expect(banner).to_have_class(f"status {tone}")
        expect(page.locator("#headline")).to_contain_text(headline)
        assert page.locator("#headline").inner_text().startswith(headline)
        assert page.title().startswith(f"{page.locator('#headline').inner_text()}, {document['number']} ")
        assert banner_colour(page) == colour, name
        expect(banner.locator(".status__occupancy")).to_have_text(line)
        expect(page.locator("#registration")).to_have_text(document["registration_number"])
        expect(page.locator("#issuing-authority")).to_have_text(get_settings().issuing_authority)
        check = page.locator("#qr-check")
        expect(check).to_have_class(f"qr-check {qr_class}")
        expect(check.locator(".qr-check__title")).to_have_text(qr_title)
        expect(page.locator("#qr-check code")).not_to_be_visible()  # the key id waits in <details>
        # The QR box's colour follows the document: green only under the green banner.
        border = style(page, "#qr-check", "borderTopColor")
        assert border == colour, (name, border)
        if colour != GREEN:
            assert style(page, "#qr-check", "backgroundColor") == "rgb(255, 255, 255)", name
            assert page.locator(".qr-check--genuine, .status--valid, .panel--c").count() == 0, name
            boxes = page.locator(".status, .qr-check, .panel").evaluate_all(
                "els => els.map(e => getComputedStyle(e))"
                ".map(style => [style.borderLeftColor, style.backgroundColor])"
            )
            assert not [box for box in boxes if GREEN in box or PALE_GREEN in box], (name, boxes)
        shoot(page, name, width)
        if width == 360:
            for selector in ("#registration", "#headline", "#status", "#qr-check"):
                within_fold(page, selector)
        if name == "superseded":
            expect(page.locator("#newer")).to_have_text(f"Certificate {documents['certified']['number']}")
        if name == "revoked":
            expect(page.locator("#revocation-reason")).to_have_text("Weighbridge ticket forged")
        if name == "refusal":
            expect(page.get_by_text("VALID", exact=False)).to_have_count(0)


@pytest.mark.parametrize("width", [360, 1280])
def test_an_unknown_or_mistyped_number_gets_a_red_banner_with_the_forms_words(
    page: Page, documents: dict[str, dict[str, Any]], width: int
) -> None:
    page.set_viewport_size({"width": width, "height": 740 if width == 360 else 900})
    number = documents["certified"]["number"]
    wrong_letter = number[:-1] + ("A" if not number.endswith("A") else "B")
    unknown = f"{number[:9]}999999-{check_letter(number[4:8] + '999999')}"
    for name, typed, headline in (
        ("unknown", unknown, "NOT VALID: no certificate has this number"),
        ("mistyped", wrong_letter, "NOT VALID: the number is mistyped"),
    ):
        page.goto("/verify")
        page.fill("#number", typed)
        page.click("button[type=submit]")
        form_words = page.locator("#number-error").inner_text() if name == "mistyped" else None
        answer = page.goto(f"/verify/{typed}")
        assert answer is not None
        assert answer.status == 404
        expect(page.locator("#headline")).to_have_text(headline)
        assert banner_colour(page) == RED, name
        assert style(page, "#status", "borderTopColor") == RED, name
        problem = page.locator("#number-problem").inner_text()
        if form_words is not None:
            assert form_words.removeprefix("Error:").strip() == problem
        api = page.request.get(f"/api/v1/verify/{typed}")
        assert api.status == 404
        message = api.json()["detail"].removeprefix("number: ")
        assert problem == f"{message[0].upper()}{message[1:]}."
        expect(page.locator("#given-number")).to_have_text(typed)
        expect(page.locator("#qr-check")).to_have_count(0)
        expect(page.locator("#number")).to_have_value(typed)
        shoot(page, name, width)
        if width == 360:
            within_fold(page, "#headline")
            within_fold(page, "#number-problem")


@pytest.mark.parametrize("width", [360, 1280])
def test_a_tampered_qr_payload_is_called_not_genuine_first(
    page: Page, documents: dict[str, dict[str, Any]], width: int
) -> None:
    page.set_viewport_size({"width": width, "height": 740 if width == 360 else 900})
    valid, refusal = documents["certified"], documents["refusal"]
    # A genuine signature, but for another document: the paper's QR code was swapped.
    page.goto(f"/verify/{valid['number']}?p={quote(refusal['qr_payload'], safe='')}")
    check = page.locator("#qr-check")
    expect(check).to_have_class("qr-check qr-check--forged")
    expect(check.locator(".qr-check__title")).to_have_text(
        "The QR code is NOT genuine: do not rely on this paper"
    )
    expect(check).to_contain_text("it was signed for a different document from the one on record")
    title_colour = check.locator(".qr-check__title").evaluate("e => getComputedStyle(e).color")
    assert title_colour == RED
    check_box, banner_box = check.bounding_box(), page.locator("#status").bounding_box()
    assert check_box is not None
    assert banner_box is not None
    assert check_box["y"] < banner_box["y"]
    shoot(page, "tampered", width)
    if width == 360:
        within_fold(page, "#qr-check")
        within_fold(page, "#headline")


def shoot(page: Page, name: str, width: int) -> None:
    """Save the page as docs/screenshots/verify-<name>-<width>.png when asked to."""
    if TAKE_SCREENSHOTS:
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SCREENSHOTS / f"verify-{name}-{width}.png"), full_page=True)


def test_the_verify_pages_have_no_axe_violations(
    kept_context: Callable[..., BrowserContext],
    documents: dict[str, dict[str, Any]],
    axe_script: Path,
) -> None:
    page = kept_context(bypass_csp=True).new_page()
    found: dict[str, list[dict[str, Any]]] = {}
    valid, refusal = documents["certified"], documents["refusal"]
    urls = {name: path_of(document["qr_url"]) for name, document in documents.items()}
    urls["tampered"] = f"/verify/{valid['number']}?p={refusal['qr_payload']}"
    urls["mistyped"] = f"/verify/{valid['number'][:-1]}{'A' if not valid['number'].endswith('A') else 'B'}"
    for name, url in urls.items():
        page.goto(url)
        if violations := axe_violations(page, axe_script):
            found[name] = violations
    assert found == {}, found
