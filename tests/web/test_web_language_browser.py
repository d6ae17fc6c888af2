"""The language switcher on a 360 px phone, in Debian's Chromium: in every language, all five links
show in the header and nothing is wider than the screen. With TRIKECERT_SCREENSHOTS=1 each page is
saved to docs/screenshots/i18n/."""

from __future__ import annotations

from collections.abc import Callable

import pytest
from playwright.sync_api import BrowserContext

from web.webtools import SCREENSHOTS, TAKE_SCREENSHOTS

pytestmark = pytest.mark.browser

LOCALES = ("en", "ha", "yo", "ig", "pcm")


@pytest.mark.parametrize("path", ["/login", "/check/", "/no-such-page"])
def test_the_switcher_fits_a_narrow_phone_in_every_language(
    kept_context: Callable[..., BrowserContext], path: str
) -> None:
    context = kept_context(viewport={"width": 360, "height": 640})
    page = context.new_page()
    for locale in LOCALES:
        page.goto(f"/language/{locale}?next={path}")
        links = page.locator("nav.languages a")
        assert links.count() == 5
        for index in range(5):
            box = links.nth(index).bounding_box()
            assert box is not None
            assert box["x"] >= 0
            assert box["x"] + box["width"] <= 360
        assert page.locator('nav.languages a[aria-current="true"]').get_attribute("hreflang") in (
            "en-GB" if locale == "en" else locale,
        )
        assert page.evaluate("document.documentElement.scrollWidth") <= 360
        if TAKE_SCREENSHOTS:
            name = path.strip("/").replace("/", "-") or "home"
            target = SCREENSHOTS / "i18n" / f"{name}-{locale}-360.png"
            target.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(target))
