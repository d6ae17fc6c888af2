"""The trust bundle's conditional GET answered ahead of the framework: every offline checker asks for
it each time it is online, and nearly always already holds it.

A GET of /.well-known/trikecert-trust whose If-None-Match names the kept bundle, still current under the
records' change mark read now (app/marks.py: a revocation shows on the very next request), is answered
304 here with the headers the whole stack gives that answer (the bundle's, the language's Vary, the
request id, nosniff, HSTS over https), counted against the public rate limit, counted in the metrics
and written to the access log like any request. Everything else (no If-None-Match, another tag, a bundle
not kept or gone stale, a client over the limit) goes on to the app, which answers as it always does.
"""

from __future__ import annotations

import time

from fastapi import FastAPI
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.certificates.bundle_answer import accepts_gzip, bundle_response, etag_matches
from app.certificates.kept_door import BUNDLE_PATH, current_bundle
from app.certificates.public import trust_bundle
from app.certificates.trust_bundle import Built
from app.ops.public_limit import counted_public_request, public_limit
from app.ops.requests import REQUEST_ID_HEADER, record_request, request_id_of
from app.web.headers import security_headers
from app.web.language import vary_by_language
from app.web.scope import header

Headers = list[tuple[bytes, bytes]]
HANDLER = trust_bundle.__name__  # the request log names the route, as if it had answered


class BundleRevalidationFirst:
    """Answer 304 to a conditional GET of the bundle the client already holds; pass the rest on."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app
        self._heads: dict[str, Headers] = {}  # ETag -> the 304's headers before the request id

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Serve the 304, or pass the request on."""
        if scope["type"] != "http" or scope["path"] != BUNDLE_PATH:
            await self.app(scope, receive, send)
            return
        started = time.perf_counter()
        head = await self._not_modified(scope)
        if head is None:
            await self.app(scope, receive, send)
            return
        request_id = request_id_of(scope)
        headers = [*head, (REQUEST_ID_HEADER, request_id.encode()), *security_headers(scope)]
        await send({"type": "http.response.start", "status": 304, "headers": headers})
        await send({"type": "http.response.body", "body": b""})
        record_request(scope, request_id=request_id, handler=HANDLER, status=304, started=started)

    async def _not_modified(self, scope: Scope) -> Headers | None:
        """The 304's headers before the request id when the client holds the current bundle and is
        within the limit (counted here, once), else None."""
        if_none_match = header(scope, b"if-none-match")
        if if_none_match is None or counted_public_request(scope, public_limit()) is not None:
            return None
        held = await current_bundle(scope)
        if held is None:
            return None
        zipped = accepts_gzip(header(scope, b"accept-encoding") or "")
        etag = held.gzip_etag if zipped else held.etag
        return self._head(held, zipped, etag) if etag_matches(if_none_match, etag) else None

    def _head(self, held: Built, zipped: bool, etag: str) -> Headers:
        """The route's own 304 headers for this tag, with the language's Vary (made once per tag)."""
        head = self._heads.get(etag)
        if head is None:
            route_answer = bundle_response(held, "gzip" if zipped else "", etag)
            start: Message = {"headers": list(route_answer.raw_headers)}
            vary_by_language(start)
            if len(self._heads) >= 8:  # a new bundle: the old tags are asked for no more
                self._heads.clear()
            head = self._heads[etag] = start["headers"]
        return head


def install_bundle_revalidation_first(app: FastAPI) -> None:
    """Put `BundleRevalidationFirst` outside the whole middleware stack (install it after the security
    headers' layer, before liveness's)."""
    build = app.build_middleware_stack
    app.build_middleware_stack = lambda: BundleRevalidationFirst(build())  # type: ignore[method-assign]
