"""Two-factor sign-in tried in Debian's Chromium as a new administrator would, with TRIKECERT_MFA=required:
an account made with `trikecert create-user`, enrolment with a code computed by pyotp from the secret
shown on the page (its QR code read by zbarimg from screenshots at 1280 and 360 px), sign-out, a code at
sign-in, a reused code refused, a recovery code that then stops working, a revocation that asks for the
password and a code again, and all of it on the audit page. axe-core finds nothing on the enrolment,
code, confirmation and audit pages; with TRIKECERT_SCREENSHOTS=1 they are saved at 1280 and 360 px in
docs/screenshots/."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pyotp
import pytest
from playwright.sync_api import Page, expect
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.accounts.models import User
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate
from app.demo import load_demo
from web.webtools import PASSWORD, SCREENSHOTS, TAKE_SCREENSHOTS, axe_violations, make_stale

pytestmark = pytest.mark.browser

EMAIL = "chief.inspector@example.org"
STEP = 30


class Authenticator:
    """The phone's app: the code of a time step never used before, as the server will count time."""

    def __init__(self, secret: str) -> None:
        self.totp = pyotp.TOTP(secret)
        self.last_step: int | None = None

    def code(self) -> str:
        """A code the server accepts now: a step within one of its clock's, and after the last one used."""
        if STEP - time.time() % STEP < 4:  # so close to the next step that the server may count past it
            time.sleep(STEP - time.time() % STEP + 0.1)
        now = int(time.time() // STEP)
        step = now - 1 if self.last_step is None else max(self.last_step + 1, now - 1)
        if step > now + 1:
            time.sleep((step - 1) * STEP - time.time() + 0.1)
        self.last_step = step
        return str(self.totp.at(step * STEP))


def create_admin() -> str:
    """`trikecert create-user` at the command line, the password on standard input; what it prints."""
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "app.cli",
            "create-user",
            EMAIL,
            "--role",
            "admin",
            "--name",
            "Amaka Nwosu",
            "--badge",
            "FRSC-0042",
        ],
        input=PASSWORD + "\n",
        capture_output=True,
        text=True,
        env=os.environ.copy(),
        check=True,
    )
    return done.stdout


def look(page: Page, name: str, axe: Path) -> None:
    """axe-core finds nothing here; the page is saved at both widths when screenshots are asked for."""
    assert axe_violations(page, axe) == [], name
    if TAKE_SCREENSHOTS:
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SCREENSHOTS / f"{name}-1280.png"), full_page=True)
        page.set_viewport_size({"width": 360, "height": 740})
        page.screenshot(path=str(SCREENSHOTS / f"{name}-360.png"), full_page=True)
        page.set_viewport_size({"width": 1280, "height": 900})


def scanned_qr(page: Page, width: int, folder: Path) -> str:
    """What a phone's scanner reads from the page's screenshot at this width (zbarimg), after checking
    that the whole code is inside the page."""
    page.set_viewport_size({"width": width, "height": 900})
    box = page.locator(".enrol-qr svg").bounding_box()
    assert box is not None
    assert box["x"] >= 0
    assert box["x"] + box["width"] <= width
    assert box["width"] >= 150  # big enough to scan from a screen
    shot = folder / f"enrol-{width}.png"
    page.screenshot(path=str(shot), full_page=True)
    done = subprocess.run(
        ["zbarimg", "--quiet", "--raw", str(shot)], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, f"zbarimg found no QR code at {width} px: {done.stderr}"
    return done.stdout.strip()


def sign_in(page: Page) -> None:
    page.goto("/login")
    page.get_by_label("Email address").fill(EMAIL)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_role("button", name="Sign in").click()


def enter_code(page: Page, code: str) -> None:
    page.get_by_label("Code").fill(code)
    page.get_by_role("button", name="Continue").click()


def sign_out(page: Page) -> None:
    page.get_by_role("button", name="Sign out").first.click()
    expect(page).to_have_url(re.compile(r"/login\?signed_out=1$"))


def test_a_new_admin_enrols_signs_in_with_codes_and_confirms_a_revocation(
    audit_page: Page, axe_script: Path, session: Session, required: None, tmp_path: Path
) -> None:
    page = audit_page
    printed = create_admin()
    assert "at the first sign-in they set up a second factor" in printed
    admin = session.scalars(select(User).where(User.email == EMAIL)).one()
    demo = load_demo(session, config.get_settings())
    assert demo.inspection is not None
    number = issue_certificate(
        session, inspection_id=demo.inspection.id, actor=Actor.of_user(admin), settings=config.get_settings()
    ).certificate.number

    # First sign-in: nothing opens before the second factor is set up.
    sign_in(page)
    expect(page).to_have_url(re.compile(r"/account/two-factor"))
    expect(page.get_by_role("heading", level=1)).to_have_text("Set up your second factor")
    expect(page.locator(".enrol-qr svg")).to_be_visible()
    secret = page.locator("#secret").inner_text()
    for width in (1280, 360):
        scanned = pyotp.parse_uri(scanned_qr(page, width, tmp_path))
        assert (scanned.secret, scanned.name) == (secret, EMAIL), width
    page.set_viewport_size({"width": 1280, "height": 900})
    look(page, "two-factor-enrol", axe_script)
    phone = Authenticator(secret)
    page.get_by_label("Code from the app").fill(phone.code())
    page.get_by_role("button", name="Confirm and turn on").click()
    expect(page.get_by_role("heading", level=1)).to_have_text("Your recovery codes")
    recovery = page.locator("#recovery-codes code").all_inner_texts()
    assert len(recovery) == 10
    page.get_by_role("link", name="I have kept them: continue").click()
    sign_out(page)

    # Signing in again takes a code; the same code twice does not work.
    sign_in(page)
    expect(page).to_have_url(re.compile(r"/login/code"))
    expect(page.get_by_role("navigation", name="Main")).to_have_count(0)  # nothing opens before the code
    look(page, "two-factor-code", axe_script)
    used = phone.code()
    enter_code(page, used)
    expect(page.get_by_role("navigation", name="Main")).to_contain_text("Audit log")
    sign_out(page)
    sign_in(page)
    enter_code(page, used)
    expect(page.locator("#code-error")).to_contain_text("not right or was used already")

    # A recovery code signs in once.
    enter_code(page, recovery[0])
    expect(page.get_by_role("status")).to_contain_text("Signed in with a recovery code; it no longer works.")
    expect(page.get_by_role("status")).to_contain_text("9 recovery codes are left")

    # Revoking after five minutes asks again; the used recovery code is refused there too.
    make_stale(session)
    page.goto(f"/certificates/{number}")
    page.get_by_label("Reason").fill("Weighbridge ticket forged")
    page.get_by_role("button", name=re.compile("^Revoke")).click()
    expect(page.get_by_role("heading", level=1)).to_have_text("Confirm it is you")
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_label("Code").fill(recovery[0])
    page.get_by_role("button", name="Confirm and continue").click()
    expect(page.locator("#reauth_code-error")).to_contain_text("not right or was used already")
    look(page, "two-factor-confirm", axe_script)
    page.get_by_label("Password").fill(PASSWORD)
    page.get_by_label("Code").fill(phone.code())
    page.get_by_role("button", name="Confirm and continue").click()
    expect(page.locator("#headline")).to_contain_text("REVOKED")

    # All of it is on the audit page, and the record is intact.
    page.goto("/admin/audit")
    expect(page.get_by_role("status").first).to_contain_text("The record is intact")
    table = page.locator("table").inner_text()
    for action in (
        "user: second factor enrolled",
        "sign in: success",
        "user: recovery code used",
        "user: reauthentication failed",
        "user: reauthenticated",
        "certificate: revoked",
        "sign out",
    ):
        assert action in table, action
    look(page, "audit-log", axe_script)
