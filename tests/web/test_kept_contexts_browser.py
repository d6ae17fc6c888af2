"""A kept browser context (tests/web/kept_contexts.py) is left after a test as a new one starts: what a
test sets in it is gone for the next."""

from __future__ import annotations

from collections.abc import Callable

import pytest
from playwright.sync_api import BrowserContext, Route

from web.kept_contexts import Kept, left_as_new

pytestmark = pytest.mark.browser
LEFT = {"width": 333, "height": 333}  # options no other test asks for: a context of this test's own


def test_what_a_test_leaves_in_a_kept_context_is_gone_for_the_next(
    kept_context: Callable[..., BrowserContext], kept_contexts: dict[str, Kept], live_server: str
) -> None:
    context = kept_context(viewport=LEFT)
    page = context.new_page()
    page.goto("/check/")  # the offline checker: its service worker registers
    registered = "navigator.serviceWorker.ready.then(() => navigator.serviceWorker.getRegistrations())"
    assert page.evaluate(f"{registered}.then(found => found.length)") == 1
    page.evaluate("localStorage.setItem('left', 'behind'); document.cookie = 'left=behind; path=/'")
    assert "left" in {cookie["name"] for cookie in context.cookies()}

    def refused(route: Route) -> None:
        route.abort()

    context.route("**/static/**", refused)
    context.set_extra_http_headers({"X-Left": "behind"})
    context.set_offline(True)

    kept = next(each for each in kept_contexts.values() if each.context is context)
    left_as_new(kept, live_server)  # what kept_context does after each test

    assert context.pages == [kept.keeper]
    assert context is kept_context(viewport=LEFT)
    page = context.new_page()
    with page.expect_request("**/static/app.css") as styles:
        page.goto("/login")  # online again
    assert styles.value.response() is not None  # no longer routed away
    assert "x-left" not in styles.value.all_headers()
    assert "left" not in {cookie["name"] for cookie in context.cookies()}
    assert page.evaluate("localStorage.length") == 0
    assert page.evaluate("navigator.serviceWorker.getRegistrations().then(found => found.length)") == 0
