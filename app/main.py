"""create_app(): the FastAPI application with its routers, middleware and error handlers;
create_served_app(): the same, as each worker process of `trikecert serve` runs it."""

from __future__ import annotations

import gc
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import anyio.to_thread
from fastapi import FastAPI

import app.models  # noqa: F401  (every table known to the mapper, whichever route loads first)
from app import GC_THRESHOLDS_FOUND, __version__
from app.api.errors import install_error_handlers
from app.api.limits import BodySizeLimit
from app.certificates.kept_door import KeptAnswersFirst
from app.certificates.public import public_router
from app.composition import api_router, callback_routers, hot_router, kept_endpoints, page_routers
from app.config import get_settings
from app.ops.bundle_first import install_bundle_revalidation_first
from app.ops.docs import install_docs
from app.ops.health import router as health_router
from app.ops.liveness import install_liveness_first
from app.ops.metrics import router as metrics_router
from app.ops.public_limit import PublicRateLimit
from app.ops.requests import RequestContext, configure_logging
from app.web.headers import install_security_headers
from app.web.language import LanguageMiddleware, language_router
from app.web.setup import install_web

DESCRIPTION = """\
Lateral stability certification of three- and four-wheeled taxis: the delta keke (one front wheel,
two rear), the tadpole trike (two front, one rear) and the quadricycle (two and two).

A weighbridge station registers a vehicle with its axle layout, then submits the wheel readings of
one weighing. The answer is the study's Table 4: for every loading case (empty, driver, driver +
1, 2, 3 passengers) the total weight, the weight on the rear wheel(s), the Lateral Stability Factor
(LSF = rear / total), the variance (limit - LSF) and the verdict. The limit is the rear wheels'
share of the tyres: 2/3 for the delta, 1/3 for the tadpole, 1/2 for the quadricycle. A case
complies only if its LSF is below the limit, decided in exact arithmetic.

Every call needs `Authorization: Bearer <station key>`, except the public
`GET /api/v1/verify/{number}`. Errors are JSON
`{"detail": ..., "errors": [{"field", "rule", "message"}]}`.
"""


@asynccontextmanager
async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
    """At most `worker_threads` routes run at once; the others wait in the event loop, holding nothing."""
    anyio.to_thread.current_default_thread_limiter().total_tokens = get_settings().worker_threads
    yield


def create_app() -> FastAPI:
    """Build the application from the current settings."""
    settings = get_settings()
    configure_logging()
    app = FastAPI(
        title="trikecert",
        version=__version__,
        description=DESCRIPTION,
        lifespan=lifespan,
        docs_url=None,  # install_docs: served from the package, not a CDN
        redoc_url=None,
        # The service exports no OpenTelemetry (its metrics are Prometheus's, app/ops/metrics.py); off,
        # FastAPI stops asking the global providers at every request whether someone set one up.
        telemetry={"tracing": False, "metrics": False, "logs": False},
    )
    install_error_handlers(app)
    # Innermost: a kept public verification is answered inside every middleware, before the routing.
    app.add_middleware(KeptAnswersFirst, endpoints=kept_endpoints)
    app.add_middleware(BodySizeLimit, max_bytes=settings.max_body_bytes)
    app.add_middleware(PublicRateLimit)  # inside the request log and the pages' headers
    app.include_router(hot_router)  # first: a submission is matched before any other route
    app.include_router(health_router)
    app.include_router(api_router)
    app.include_router(public_router)
    app.include_router(metrics_router)
    app.include_router(language_router)
    for router in callback_routers:
        app.include_router(router)
    install_docs(app)
    install_web(app, page_routers)  # the officer pages; after the API's error handlers
    app.add_middleware(LanguageMiddleware)  # inside the request log: errors it meets are logged
    app.add_middleware(RequestContext)
    install_security_headers(app)
    install_bundle_revalidation_first(app)  # outside every middleware: it gives their headers itself
    install_liveness_first(app)  # outermost: a probe meets none of the above

    return app


def create_served_app() -> FastAPI:
    """The application as a worker process of `trikecert serve` runs it: built, then every object
    alive so far (modules, the ORM's mappings, the schemas) frozen out of the garbage collector's way."""
    served = create_app()
    # Each full collection walked the hundreds of thousands of objects a worker holds from its
    # start, pausing the requests in flight: the p99 of a submission at 32 connections halved
    # without those walks (bench/RESULTS.md). Only the served process: a test process builds many
    # apps, and what a freeze holds is never collected.
    gc.collect()
    gc.freeze()
    gc.set_threshold(*GC_THRESHOLDS_FOUND)  # raised while the app was imported (app/__init__.py)
    return served
