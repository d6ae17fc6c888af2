"""Mount the officer pages on the app: static files, HTML errors and page headers around the routers
the composition root (app/composition.py) hands in."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from fastapi import APIRouter, FastAPI
from fastapi.staticfiles import StaticFiles

from app.web.errors import install_web_error_handlers
from app.web.headers import PageHeaders

STATIC_DIR = Path(__file__).resolve().parent / "static"


def install_web(app: FastAPI, routers: Iterable[APIRouter]) -> None:
    """Add the pages; call after the API's error handlers are installed, so API answers stay JSON."""
    install_web_error_handlers(app)
    app.mount("/static", StaticFiles(directory=STATIC_DIR), name="static")
    for router in routers:
        app.include_router(router)
    app.add_middleware(PageHeaders)
