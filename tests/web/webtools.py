"""Helpers of the page tests: accounts, the study's readings, posting forms as a browser would."""

from __future__ import annotations

import os
import re
import time
from datetime import timedelta
from decimal import Decimal
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pyotp
from fastapi.testclient import TestClient
from httpx2 import Response
from playwright.sync_api import Page
from sqlalchemy import update
from sqlalchemy.orm import Session
from study_data import STUDY_TYPE_READINGS

from app.accounts.models import UserSession
from app.db import utcnow
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import Rules, WheelReadings
from app.stability.model import WHEELS
from app.vehicles.service import register_vehicle

PASSWORD = "correct horse battery"
OFFICER_EMAIL = "officer@example.org"
ADMIN_EMAIL = "admin@example.org"
STUDY_SEATS = [("driver", Decimal("0.9303"))] + [("passenger", Decimal("1.6303"))] * 3
STUDY_READINGS = {
    "front_kg_1": "108",
    "left_rear_kg_1": "115",
    "right_rear_kg_1": "135",
    "overall_kg_1": "359",
}

REPO = Path(__file__).resolve().parents[2]
# Debian's headless shell (the package chromium-headless-shell, built from the same source as its
# chromium, the build Playwright itself runs headless) where it is installed: the same pages at two
# thirds of the full browser's CPU (measured: bench/RESULTS.md, issue 26, 2026-12-06). Else chromium.
HEADLESS_SHELL = "/usr/bin/chromium-headless-shell"
CHROMIUM = os.environ.get(
    "TRIKECERT_CHROMIUM", HEADLESS_SHELL if os.access(HEADLESS_SHELL, os.X_OK) else "/usr/bin/chromium"
)
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
AXE_PATH = Path(os.environ.get("TRIKECERT_AXE_PATH", str(REPO / "node_modules" / "axe-core" / "axe.min.js")))
SCREENSHOTS = REPO / "docs" / "screenshots"
TAKE_SCREENSHOTS = os.environ.get("TRIKECERT_SCREENSHOTS") == "1"


_TOKEN = re.compile(r'name="(csrf_token|form_token)" value="([^"]*)"')


def wheel_readings(front: int, left: int, right: int, overall: int) -> WheelReadings:
    """One reading per wheel and the overall weight, in kg."""
    return WheelReadings(*((Decimal(kg),) for kg in (front, left, right, overall)))


def hidden(html: str, name: str = "csrf_token") -> str:
    """The value of a hidden token field in a page."""
    for found, value in _TOKEN.findall(html):
        if found == name:
            return str(value)
    raise AssertionError(f"no {name} in the page")


def sign_in(client: TestClient, email: str, password: str = PASSWORD, **extra: str) -> Response:
    """Post the sign-in form as a browser would (token from the page, cookie kept by the client)."""
    page = client.get("/login")
    form = {"email": email, "password": password, "csrf_token": hidden(page.text), **extra}
    response: Response = client.post("/login", data=form, follow_redirects=False)
    return response


class _Inputs(HTMLParser):
    """Collects the name and value of every text-like input of a page, as a browser would send them."""

    def __init__(self) -> None:
        super().__init__()
        self.values: dict[str, str] = {}

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        kind = found.get("type") or "text"
        if tag == "input" and found.get("name") and (kind not in ("radio", "checkbox") or "checked" in found):
            self.values.setdefault(str(found["name"]), found.get("value") or "")


def form_values(html: str) -> dict[str, str]:
    """Every input of the page with the value it shows (the sign-out form's token included)."""
    parser = _Inputs()
    parser.feed(html)
    return parser.values


def post_form(client: TestClient, page_url: str, action: str, fields: dict[str, str]) -> Response:
    """Open a form page, then post it as a browser would: what the page shows, changed by `fields`."""
    page = client.get(page_url)
    assert page.status_code == 200, page.text
    response: Response = client.post(
        action, data={**form_values(page.text), **fields}, follow_redirects=False
    )
    return response


def code_at(secret: str, steps_from_now: int = 0) -> str:
    """What an authenticator app shows for this secret, `steps_from_now` time steps from now."""
    return pyotp.TOTP(secret).at(time.time() + 30 * steps_from_now)


def enrol(client: TestClient) -> tuple[str, list[str]]:
    """Sign-in's first step done: open the enrolment page, confirm a code; the secret and recovery codes."""
    secret, codes, _used = enrol_with_code(client)
    return secret, codes


def enrol_with_code(client: TestClient) -> tuple[str, list[str], str]:
    """As enrol, and the code it confirmed with (used up: a replay of it must be refused, whichever
    30-second step the test has reached since)."""
    page = client.get("/account/two-factor")
    assert page.status_code == 200
    secret = re.search(r'<code id="secret" class="secret">([A-Z2-7]+)</code>', page.text)
    assert secret, page.text
    assert "<svg" in page.text  # the QR code, drawn on the page itself
    used = code_at(secret[1], -1)
    form = {"csrf_token": hidden(page.text), "next": "/", "code": used}
    shown = client.post("/account/two-factor", data=form)
    assert shown.status_code == 200, shown.text
    codes = re.findall(r"<li><code>([A-Z2-9]{4}-[A-Z2-9]{4}-[A-Z2-9]{4}-[A-Z2-9]{4})</code></li>", shown.text)
    assert "They are shown only now" in shown.text
    return secret[1], codes, used


def axe_violations(page: Page, script: Path) -> list[dict[str, Any]]:
    """Run axe-core on the page as it stands; every violation with the elements it names."""
    page.add_script_tag(path=str(script))
    # Every rule runs; only the violations list every element (the passes name their rule and one
    # element each), which halves axe's time on a long page.
    result: dict[str, Any] = page.evaluate("async () => axe.run(document, {resultTypes: ['violations']})")
    assert len(result["passes"]) > 10, "axe-core did not run its rules"
    return [
        {"id": v["id"], "impact": v["impact"], "help": v["help"], "nodes": [n["target"] for n in v["nodes"]]}
        for v in result["violations"]
    ]


def save_at_both_widths(page: Page, folder: Path, name: str) -> None:
    """The page as it stands, full length, saved as folder/NAME-1280.png and folder/NAME-360.png; the
    viewport is put back to 1280 px."""
    folder.mkdir(parents=True, exist_ok=True)
    page.set_viewport_size({"width": 1280, "height": 900})
    page.screenshot(path=str(folder / f"{name}-1280.png"), full_page=True)
    page.set_viewport_size({"width": 360, "height": 740})
    page.screenshot(path=str(folder / f"{name}-360.png"), full_page=True)
    page.set_viewport_size({"width": 1280, "height": 900})


def weigh_study_fleet(session: Session, *, model: str = "RE", suffix: str = "") -> dict[str, int]:
    """The reference's section 7: three vehicles of the study's model weighed with its readings.

    Returns registration -> inspection id (each recorded as an officer's inspection); `suffix` is
    added to every registration number.
    """
    found = {}
    for study_registration, readings in STUDY_TYPE_READINGS.items():
        registration = study_registration + suffix
        register_vehicle(
            session,
            registration_number=registration,
            make="Bajaj",
            model=model,
            model_year=2012,
            wheelbase_m=Decimal("2.000"),
            seats=STUDY_SEATS,
        )
        wheels = WheelReadings(*((Decimal(readings[w]),) for w in WHEELS))
        request = InspectionRequest(registration_number=registration, readings=wheels)
        found[registration] = record_inspection(session, request=request, rules=Rules()).id
    return found


def make_stale(session: Session, minutes: int = 6) -> None:
    """Every browser session last proved who it is `minutes` ago (past the five that need no asking)."""
    session.execute(update(UserSession).values(verified_at=utcnow() - timedelta(minutes=minutes)))
    session.commit()
