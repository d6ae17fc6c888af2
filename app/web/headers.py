"""ASGI middleware: every answer carries nosniff (and HSTS over https) and no Server header; pages
are also never cached (the back button after sign-out shows nothing) and are locked down by a strict
Content-Security-Policy, which API and documentation answers do without. No page runs a script
(`script-src 'none'`) except the offline checker at /check/, which sets its own policy
(app/checker/views.py)."""

from __future__ import annotations

from fastapi import FastAPI
from starlette.datastructures import MutableHeaders
from starlette.types import ASGIApp, Message, Receive, Scope, Send

# One year; no includeSubDomains or preload: the service cannot vouch for its sibling hosts.
HSTS = "max-age=31536000"

PAGE_HEADERS = {
    "Cache-Control": "no-store",
    "X-Content-Type-Options": "nosniff",
    "X-Frame-Options": "DENY",
    "Referrer-Policy": "same-origin",
    "Content-Security-Policy": (
        "default-src 'self'; img-src 'self' data:; style-src 'self'; script-src 'none'; "
        "object-src 'none'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'"
    ),
}
UNTOUCHED_PREFIXES = ("/api/", "/docs", "/redoc", "/openapi.json", "/static/")


class PageHeaders:
    """Add the page headers to every HTML answer outside the API, docs and static files."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Pass through, adding headers to page responses."""
        if scope["type"] != "http" or str(scope.get("path", "")).startswith(UNTOUCHED_PREFIXES):
            await self.app(scope, receive, send)
            return

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                if headers.get("content-type", "").startswith("text/html") or message["status"] in (302, 303):
                    for name, value in PAGE_HEADERS.items():
                        headers.setdefault(name, value)
            await send(message)

        await self.app(scope, receive, send_with_headers)


class SecurityHeaders:
    """nosniff on every answer, HSTS on those sent over https, and never a Server header.

    The scheme is https when uvicorn serves TLS itself, or when a proxy listed in
    TRIKECERT_FORWARDED_ALLOW_IPS said so with X-Forwarded-Proto (uvicorn's proxy headers);
    the header from anyone else is ignored before it gets here.
    """

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Pass through, setting the headers on the response's start."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        https = scope.get("scheme") == "https"

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                del headers["server"]
                headers.setdefault("X-Content-Type-Options", "nosniff")
                if https:
                    headers.setdefault("Strict-Transport-Security", HSTS)
            await send(message)

        await self.app(scope, receive, send_with_headers)


def security_headers(scope: Scope) -> list[tuple[bytes, bytes]]:
    """What SecurityHeaders adds to an answer that has neither: for a door answering ahead of it."""
    headers = [(b"x-content-type-options", b"nosniff")]
    if scope.get("scheme") == "https":
        headers.append((b"strict-transport-security", HSTS.encode()))
    return headers


def install_security_headers(app: FastAPI) -> None:
    """Wrap the app's whole middleware stack, so that even Starlette's own 500 carries the headers."""
    build = app.build_middleware_stack
    # add_middleware() would sit inside ServerErrorMiddleware, whose 500 answers would then go bare.
    app.build_middleware_stack = lambda: SecurityHeaders(build())  # type: ignore[method-assign]
