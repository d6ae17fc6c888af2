"""Which language a request is answered in: the cookie the switcher sets, else Accept-Language.

The JSON API (/api/…) always answers in English: its codes are stable and its clients are programs.
"""

from __future__ import annotations

from http.cookies import SimpleCookie
from urllib.parse import quote

from fastapi import APIRouter, HTTPException, Request
from starlette.datastructures import MutableHeaders
from starlette.responses import RedirectResponse
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.i18n.active import current_locale, use_locale
from app.i18n.locales import ENGLISH, HTML_LANG, LOCALES, NATIVE_NAMES, known_locale, negotiate
from app.web.cookies import is_secure
from app.web.scope import header

LANGUAGE_COOKIE = "trikecert_lang"
ONE_YEAR = 365 * 24 * 3600
# A page's words follow these two request headers: a shared cache must keep one copy per value.
VARY = ("Accept-Language", "Cookie")

language_router = APIRouter(include_in_schema=False)


def request_locale(scope: Scope) -> str:
    """The locale for a request: English on the API, else the cookie's, else Accept-Language's."""
    if scope.get("path", "").startswith("/api/"):
        return ENGLISH
    cookie_header = header(scope, b"cookie")
    if cookie_header:
        try:
            morsel = SimpleCookie(cookie_header).get(LANGUAGE_COOKIE)
        except Exception:  # a malformed Cookie header chooses nothing: fall through
            morsel = None
        chosen = known_locale(morsel.value) if morsel is not None else None
        if chosen is not None:
            return chosen
    return negotiate(header(scope, b"accept-language"))


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
        if scope.get("path", "").startswith("/api/"):
            with use_locale(locale):
                await self.app(scope, receive, send)
            return

        async def send_varying(message: Message) -> None:
            if message["type"] == "http.response.start":
                vary_by_language(message)
            await send(message)

        with use_locale(locale):
            await self.app(scope, receive, send_varying)


def vary_by_language(start: Message) -> None:
    """Name the request headers a page's words follow in the Vary of a response's start message."""
    headers = MutableHeaders(scope=start)
    present = {v.strip().lower() for v in headers.get("vary", "").split(",") if v.strip()}
    for name in VARY:
        if name.lower() not in present:
            headers.add_vary_header(name)


def local_path(target: str | None) -> str:
    """The target if it is a path on this site ('/…', not '//host' or '/\\host'), else '/'."""
    if not target or not target.startswith("/") or target.startswith(("//", "/\\")):
        return "/"
    if any(ord(c) < 0x20 or c == "\x7f" for c in target):  # no header splitting, no hidden hosts
        return "/"
    return target


def language_links(request: Request) -> list[dict[str, str | bool]]:
    """The switcher's links: each language in its own name, the active one marked current."""
    here = request.url.path + (f"?{request.url.query}" if request.url.query else "")
    active = current_locale()
    return [
        {
            "href": f"/language/{code}?next={quote(here, safe='/')}",
            "name": NATIVE_NAMES[code],
            "lang": HTML_LANG[code],
            "current": code == active,
        }
        for code in LOCALES
    ]


@language_router.get("/language/{locale}")
def choose_language(locale: str, request: Request, next: str | None = None) -> RedirectResponse:
    """Remember the reader's language for a year and send them back to the page they were on."""
    if locale not in LOCALES:
        raise HTTPException(status_code=404)
    response = RedirectResponse(local_path(next), status_code=303)
    response.set_cookie(
        LANGUAGE_COOKIE,
        locale,
        max_age=ONE_YEAR,
        path="/",
        samesite="lax",
        secure=is_secure(request),
        httponly=False,  # nothing secret: the choice of a language
    )
    return response
