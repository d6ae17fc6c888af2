"""The per-address rate limit of the public verification: 429 with Retry-After beyond it, a page for
a browser and the API's error body for a program.

An ASGI middleware: a request of another path costs one string comparison, and a counted one a
dictionary look-up under a lock (app.api.address_limits); nothing reaches the database.
"""

from __future__ import annotations

from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.types import ASGIApp, Receive, Scope, Send

from app.api.address_limits import client_address, windows
from app.api.windows import RateLimit
from app.config import get_settings
from app.stations.rate_limit import RATE_LIMIT_RULE

# What anyone may ask without signing in: the verify form and pages, the QR codes' short addresses,
# the JSON verification, and the service's public files under /.well-known/ (the published keys; a
# trust bundle beside them). A prefix match (str.startswith takes a tuple) keeps the check cheap.
PUBLIC_PATHS = ("/verify", "/v/", "/V/", "/api/v1/verify/", "/.well-known/trikecert-", "/reminders")
# Where a request's count is kept in its scope once counted (its Retry-After, or None within the limit).
COUNTED = "trikecert.public_retry_after"


def wants_json(scope: Scope) -> bool:
    """A program's request: the API, a public JSON file, or a client asking for JSON before HTML."""
    path: str = scope["path"]
    if path.startswith(("/api/", "/.well-known/")):
        return True
    from app.certificates.verify_json import wants_json as asks_for_json  # the verify page's own rule

    return asks_for_json(Request(scope))


def too_many(scope: Scope, limit: RateLimit, retry_after: int) -> Response:
    """The refusal: the API's error body, or a page that says when to try again."""
    headers = {"Retry-After": str(retry_after), "Cache-Control": "no-store"}
    if wants_json(scope):
        message = (
            f"client: more than {limit.limit} verification requests came from this address in "
            f"{limit.window_seconds} s; retry after {retry_after} s"
        )
        problem = {"field": "client", "rule": RATE_LIMIT_RULE, "message": message}
        body = {"detail": message, "errors": [problem]}
        return JSONResponse(body, status_code=429, headers=headers)
    from app.web.errors import error_page

    page = error_page(
        Request(scope),
        429,
        f"Too many certificate checks came from your network in a short time. Wait {retry_after} "
        "seconds, then check the certificate again.",
        title="Please wait a moment",
        retry_url=_same_address(scope),
    )
    page.headers.update(headers)
    return page


def _same_address(scope: Scope) -> str:
    query = scope.get("query_string", b"").decode("latin-1")
    return f"{scope['path']}?{query}" if query else str(scope["path"])


class PublicRateLimit:
    """At most `public_rate_limit` public verification requests per client address per window."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Count a public request of its address; beyond the limit answer 429 instead of the route."""
        if scope["type"] == "http" and scope["path"].startswith(PUBLIC_PATHS):
            limit = public_limit()
            retry_after = counted_public_request(scope, limit)
            if retry_after is not None:
                await too_many(scope, limit, retry_after)(scope, receive, send)
                return
        await self.app(scope, receive, send)


def public_limit() -> RateLimit:
    """The public doors' limit under the current settings."""
    settings = get_settings()
    return RateLimit(settings.public_rate_limit, settings.public_rate_window_seconds)


def counted_public_request(scope: Scope, limit: RateLimit) -> int | None:
    """Count the request against its address once (a door ahead of the stack may have counted it
    already): None while within the limit, else the seconds to wait."""
    if COUNTED not in scope:
        scope[COUNTED] = windows(scope, "public", limit).count(client_address(scope))
    retry_after: int | None = scope[COUNTED]
    return retry_after
