"""/docs and /redoc in a real browser with every other host cut off (issue 10, item 8): the pages
come from the package, list the operations, and the browser asks nothing of any other host.

The pages are opened under a host name that is not loopback (mapped to the test server by
Chromium's resolver), as a regulator's intranet would name the service: Swagger UI treats
localhost specially (it hides its online-validator badge there), so loopback would hide a leak.
"""

from __future__ import annotations

import json
import re
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from urllib.parse import urlsplit

import pytest
from playwright.sync_api import Browser, BrowserType, ConsoleMessage, Page, Route, expect

from web.webtools import CHROMIUM_ARGS

pytestmark = pytest.mark.browser

HOST = "trikecert.intranet.test"
# ms to wait for the first operation: a 1-2 MB bundle on a loaded machine (not a speed test)
RENDERED = 60_000
# The one thing the policy stops: ReDoc's footer logo on its maker's CDN (it then hides the image).
REFUSED_IMAGE = re.compile(
    r"^(Loading|Refused to load) the image 'https://cdn\.redoc\.ly/[^']*'.*Content Security Policy"
)


@dataclass
class Offline:
    """The cut-off page, the service's address under its intranet name, what leaked, console errors."""

    page: Page
    base: str
    leaks: list[str]
    errors: list[str]

    def assert_self_contained(self) -> None:
        """Nothing was asked of another host, and nothing failed but the policy's refusal of that logo."""
        self.page.wait_for_load_state("networkidle")
        assert self.leaks == []
        assert [error for error in self.errors if not REFUSED_IMAGE.match(error)] == []


@pytest.fixture
def offline(browser_type: BrowserType, chromium: str, live_server: str) -> Iterator[Offline]:
    """A page whose requests to any host but the service are recorded and aborted."""
    port = urlsplit(live_server).port
    browser: Browser = browser_type.launch(
        executable_path=chromium,
        args=[*CHROMIUM_ARGS, f"--host-resolver-rules=MAP {HOST} 127.0.0.1"],
        headless=True,
    )
    leaks: list[str] = []
    errors: list[str] = []

    def only_the_service(route: Route) -> None:
        if urlsplit(route.request.url).hostname == HOST:
            route.continue_()
        else:
            leaks.append(route.request.url)
            route.abort()

    context = browser.new_context(viewport={"width": 1280, "height": 900})
    context.route("**/*", only_the_service)
    page = context.new_page()

    def on_console(message: ConsoleMessage) -> None:
        # A script the page's policy refused would leave the page half-built: count it as a failure.
        if message.type == "error":
            errors.append(message.text)

    page.on("console", on_console)
    try:
        yield Offline(page, f"http://{HOST}:{port}", leaks, errors)
    finally:
        context.close()
        browser.close()


def _operations(live_server: str) -> list[tuple[str, str, str]]:
    """(method, path, summary) of every operation in the OpenAPI schema."""
    with urllib.request.urlopen(f"{live_server}/openapi.json", timeout=10) as response:
        schema = json.loads(response.read())
    return [
        (method.upper(), path, operation["summary"])
        for path, operations in schema["paths"].items()
        for method, operation in operations.items()
    ]


def test_swagger_ui_lists_every_operation_with_the_network_cut_off(
    offline: Offline, live_server: str
) -> None:
    page = offline.page
    operations = _operations(live_server)
    assert len(operations) >= 5
    page.goto(f"{offline.base}/docs")
    expect(page.locator(".opblock").first).to_be_visible(timeout=RENDERED)
    expect(page.locator(".opblock")).to_have_count(len(operations))
    for method, path, _summary in operations:
        block = page.locator(f".opblock-{method.lower()}", has=page.locator(f'[data-path="{path}"]'))
        expect(block).to_have_count(1)
    offline.assert_self_contained()
    assert offline.errors == []


def test_redoc_lists_every_operation_with_the_network_cut_off(offline: Offline, live_server: str) -> None:
    page = offline.page
    operations = _operations(live_server)
    page.goto(f"{offline.base}/redoc")
    expect(page.locator("h2").first).to_be_attached(timeout=RENDERED)
    for _method, _path, summary in operations:
        expect(page.locator("h2", has_text=summary).first).to_be_attached()
    expect(page.get_by_role("img", name="redocly logo")).to_have_count(0)  # hidden, not a broken image
    offline.assert_self_contained()
