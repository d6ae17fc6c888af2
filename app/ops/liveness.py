"""GET /healthz answered ahead of the framework, as a load balancer polls it many times a second.

The answer is the route's own (app/ops/health.py): `{"status":"ok"}` with the headers every answer
carries (nosniff, HSTS over https, the request id, never a Server header), and the probe is counted
in the metrics and written to the access log like any request. What it skips is the work no probe
needs: the framework's middleware, routing and exception handling, about three quarters of its cost.
"""

from __future__ import annotations

import time

from fastapi import FastAPI
from starlette.types import ASGIApp, Receive, Scope, Send

from app.ops.health import HEALTHY_BODY
from app.ops.requests import REQUEST_ID_HEADER, record_request, request_id_of
from app.web.headers import security_headers

PATH = "/healthz"
_HEADERS = [
    (b"content-type", b"application/json"),
    (b"content-length", str(len(HEALTHY_BODY)).encode()),
]


class LivenessFirst:
    """Answer GET /healthz at once; hand every other request to the app."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Serve the probe, or pass the request on."""
        if scope["type"] != "http" or scope["path"] != PATH or scope["method"] != "GET":
            await self.app(scope, receive, send)
            return
        started = time.perf_counter()
        request_id = request_id_of(scope)
        headers = [*_HEADERS, (REQUEST_ID_HEADER, request_id.encode()), *security_headers(scope)]
        await send({"type": "http.response.start", "status": 200, "headers": headers})
        await send({"type": "http.response.body", "body": HEALTHY_BODY})
        record_request(scope, request_id=request_id, handler="healthz", status=200, started=started)


def install_liveness_first(app: FastAPI) -> None:
    """Put `LivenessFirst` outside the whole middleware stack (install it last)."""
    build = app.build_middleware_stack
    app.build_middleware_stack = lambda: LivenessFirst(build())  # type: ignore[method-assign]
