"""Which language a request is answered in: the cookie the switcher sets, else Accept-Language.

The JSON API (/api/…) always answers in English: its codes are stable and its clients are programs.
"""

from __future__ import annotations

from http.cookies import SimpleCookie

from starlette.types import ASGIApp, Receive, Scope, Send

from app.i18n.active import use_locale
from app.i18n.locales import ENGLISH, known_locale, negotiate

LANGUAGE_COOKIE = "trikecert_lang"


def _header(scope: Scope, name: bytes) -> str | None:
    for key, value in scope.get("headers", ()):
        if key == name:
            return str(value.decode("latin-1"))
    return None


def request_locale(scope: Scope) -> str:
    """The locale for a request: English on the API, else the cookie's, else Accept-Language's."""
    if scope.get("path", "").startswith("/api/"):
        return ENGLISH
    cookie_header = _header(scope, b"cookie")
    if cookie_header:
        try:
            morsel = SimpleCookie(cookie_header).get(LANGUAGE_COOKIE)
        except Exception:  # a malformed Cookie header chooses nothing: fall through
            morsel = None
        chosen = known_locale(morsel.value) if morsel is not None else None
        if chosen is not None:
            return chosen
    return negotiate(_header(scope, b"accept-language"))


class LanguageMiddleware:
    """Make the request's locale active for everything the request runs (pages, words, PDFs)."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Answer the request in its locale."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        locale = request_locale(scope)
        scope.setdefault("state", {})["locale"] = locale
        with use_locale(locale):
            await self.app(scope, receive, send)
