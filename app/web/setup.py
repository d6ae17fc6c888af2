"""Mount the officer pages on the app: routers, static files, HTML errors and page headers."""

from __future__ import annotations

from pathlib import Path

from fastapi import FastAPI
from fastapi.staticfiles import StaticFiles

from app.accounts.admin_views import router as admin_router
from app.accounts.second_factor_views import router as second_factor_router
from app.accounts.views import router as accounts_router
from app.audit.views import router as audit_router
from app.dynamics.views import router as vehicle_dynamics_router
from app.inspections.views import router as inspections_router
from app.stations.views import router as stations_router
from app.statistics.views import router as statistics_router
from app.type_assessments.views import router as type_assessments_router
from app.vehicles.views import router as vehicles_router
from app.web.errors import install_web_error_handlers
from app.web.headers import PageHeaders
from app.web.home import router as home_router

STATIC_DIR = Path(__file__).resolve().parent / "static"


def install_web(app: FastAPI) -> None:
    """Add the pages; call after the API's error handlers are installed, so API answers stay JSON."""
    install_web_error_handlers(app)
    app.mount("/static", StaticFiles(directory=STATIC_DIR), name="static")
    for router in (
        home_router,
        accounts_router,
        second_factor_router,
        admin_router,
        audit_router,
        stations_router,
        vehicle_dynamics_router,
        vehicles_router,
        inspections_router,
        statistics_router,
        type_assessments_router,
    ):
        app.include_router(router)
    app.add_middleware(PageHeaders)
