"""Browser contexts kept for the run: a new context starts a renderer process and compiles Playwright's
scripts in it again (~0.9 core-s a test here), so the page tests that need no fresh phone take
a kept one, left after each test as a new one starts."""

from __future__ import annotations

from dataclasses import dataclass

from playwright.sync_api import BrowserContext, Page


@dataclass
class Kept:
    """A context kept for the run, and the blank page that keeps its renderer process alive."""

    context: BrowserContext
    keeper: Page


def left_as_new(kept: Kept, origin: str) -> None:
    """The context as a new one, for the one origin the tests open: every page but the keeper
    closed; the origin's cookies, storage, caches and service workers, the browser's cache, the
    permissions, routes, extra headers and the network's state undone."""
    for page in kept.context.pages:
        if page is not kept.keeper:
            page.close()
    devtools = kept.context.new_cdp_session(kept.keeper)
    devtools.send("Storage.clearDataForOrigin", {"origin": origin, "storageTypes": "all"})
    devtools.send("Network.clearBrowserCache")
    devtools.detach()
    kept.context.clear_cookies()
    kept.context.clear_permissions()
    kept.context.unroute_all()
    kept.context.set_extra_http_headers({})
    kept.context.set_offline(False)
