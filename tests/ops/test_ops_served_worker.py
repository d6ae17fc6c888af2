"""A worker process of `trikecert serve` keeps its start-up objects out of the garbage collector's
walks (a full collection over them paused the requests in flight: bench/RESULTS.md)."""

from __future__ import annotations

import argparse
import gc
from typing import Any

import pytest
import uvicorn
from fastapi.testclient import TestClient
from sqlalchemy import Engine

from app.cli import cmd_serve
from app.main import create_served_app


def test_the_served_app_freezes_what_it_holds_from_its_start_and_still_answers(engine: Engine) -> None:
    gc.unfreeze()
    assert gc.get_freeze_count() == 0
    try:
        app = create_served_app()
        assert gc.get_freeze_count() > 10_000  # the modules, mappings and schemas of a worker
        with TestClient(app) as client:
            assert client.get("/healthz").status_code == 200
    finally:
        gc.unfreeze()  # this test process goes on building apps


def test_trikecert_serve_runs_the_served_app(engine: Engine, monkeypatch: pytest.MonkeyPatch) -> None:
    served: list[tuple[Any, ...]] = []
    monkeypatch.setattr(uvicorn, "run", lambda *args, **kwargs: served.append((args, kwargs)))
    options = argparse.Namespace(no_migrate=True, workers=1, host="127.0.0.1", port=8000)
    assert cmd_serve(options) == 0
    [(args, kwargs)] = served
    assert args == ("app.main:create_served_app",)
    assert kwargs["factory"] is True
