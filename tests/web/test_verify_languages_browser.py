"""The public verify page in every state and every language on a 360 px phone, in Debian's Chromium:
nothing sticks out sideways. With TRIKECERT_SCREENSHOTS=1 the screenshots are saved to
docs/screenshots/i18n/verify-STATE-LL.png (a plain run leaves the checkout as it was):
    TRIKECERT_SCREENSHOTS=1 .venv/bin/pytest -p no:cacheprovider tests/web/test_verify_languages_browser.py
"""

from __future__ import annotations

from collections.abc import Callable
from datetime import timedelta
from decimal import Decimal

import pytest
from playwright.sync_api import BrowserContext
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.certificates import answer_cache, records
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, reissue_certificate, revoke_certificate
from app.config import get_settings
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import WheelReadings
from app.trust.numbers import check_letter
from app.vehicles.models import Vehicle
from app.vehicles.service import register_vehicle
from web.webtools import SCREENSHOTS, STUDY_SEATS, TAKE_SCREENSHOTS, wheel_readings

pytestmark = pytest.mark.browser

WIDTH = 360
LOCALES = ("en", "ha", "yo", "ig", "pcm")


@pytest.fixture
def numbers(session: Session, admin: User, study_vehicle: Vehicle) -> dict[str, str]:
    """A paper in each state by its number; 'expired' is the certified one with the clock moved on."""
    settings, rules = get_settings(), get_settings().rules()
    actor = Actor.of_user(admin)

    def issue(plate: str, wheels: WheelReadings) -> str:
        request = InspectionRequest(registration_number=plate, readings=wheels)
        inspection = record_inspection(session, request=request, rules=rules, station=None).id
        return issue_certificate(
            session, inspection_id=inspection, actor=actor, settings=settings
        ).certificate.number

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
    old = issue("BDG 252 QH", wheel_readings(200, 80, 80, 360))
    newer = reissue_certificate(session, number=old, actor=actor, reason="lost", settings=settings).number
    revoked = issue("LAG 888 YB", wheel_readings(200, 80, 80, 360))
    revoke_certificate(session, number=revoked, actor=actor, reason="Wrong wheel readings entered")
    refusal = issue("KTU 123 XA", wheel_readings(100, 120, 140, 360))
    session.commit()
    return {
        "certified": newer,
        "refusal": refusal,
        "revoked": revoked,
        "superseded": old,
        "not-found": f"TRK-2026-999999-{check_letter('2026999999')}",
        "expired": newer,
    }


def test_the_verify_page_fits_a_360_px_phone_in_every_state_and_language(
    kept_context: Callable[..., BrowserContext],
    numbers: dict[str, str],
    session: Session,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    context = kept_context(viewport={"width": WIDTH, "height": 740})
    target = SCREENSHOTS / "i18n"
    if TAKE_SCREENSHOTS:
        target.mkdir(parents=True, exist_ok=True)
    page = context.new_page()
    for state, number in numbers.items():
        if state == "expired":  # only the clock moves on (the live server runs in this process)
            found = records.find_certificate(session, number)
            assert found is not None
            later = found.expires_at + timedelta(seconds=1)
            for clock in (records, answer_cache):
                monkeypatch.setattr(clock, "utcnow", lambda later=later: later)
        for locale in LOCALES:
            page.goto(f"/language/{locale}?next=/verify/{number}")
            assert page.locator("#headline").count() == 1, (state, locale)
            assert page.locator("html").get_attribute("lang") == ("en-GB" if locale == "en" else locale)
            if TAKE_SCREENSHOTS:  # the first screen: the banner
                page.screenshot(path=str(target / f"verify-{state}-{locale}.png"))
            assert page.evaluate("document.documentElement.scrollWidth") <= WIDTH, (state, locale)
