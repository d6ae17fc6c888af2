"""The app of the current settings, lent to test after test: a new one costs more than most tests'
own requests (FastAPI builds every included route's handling anew for each app, on its first
requests: a third of a page test's time)."""

from __future__ import annotations

import json

from fastapi import FastAPI
from pydantic import SecretStr
from starlette.datastructures import State

from app.config import get_settings
from app.main import create_app
from app.ops.requests import configure_logging

_applications: dict[str, FastAPI] = {}


def application() -> FastAPI:
    """The app of the current settings, as a new one would answer: built once for these settings,
    then lent again with its state emptied (nothing else of an app outlives a request)."""
    settings = get_settings()
    key = json.dumps(
        {name: _plain(value) for name, value in settings},
        default=str,
        sort_keys=True,
    )
    app = _applications.get(key)
    if app is None:
        app = _applications[key] = create_app()
    else:
        configure_logging()  # as create_app does: a test may have changed the logging settings
    app.state = State()  # the per-app counters (rate limits) start from nothing, as in a new app
    return app


def _plain(value: object) -> object:
    """A setting's value with a secret's own value, so that two settings differing in one compare unequal."""
    return value.get_secret_value() if isinstance(value, SecretStr) else value
