"""Fixtures for the officer pages: accounts, a signed-in TestClient, the study's vehicle, and for the
browser tests the real app under uvicorn on a free port with Debian's Chromium."""

from __future__ import annotations

import os
import socket
import threading
import time
from collections.abc import Callable, Iterator
from datetime import date
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
import uvicorn
from fastapi.testclient import TestClient
from needed_tools import tool_missing
from playwright.sync_api import Browser, BrowserContext, Page
from sqlalchemy.orm import Session

from app import config
from app.accounts.models import User
from app.accounts.service import create_user
from app.main import create_app
from app.stations.details import StationDetails
from app.stations.models import Station
from app.stations.service import create_station
from app.vehicles.models import Vehicle
from app.vehicles.service import register_vehicle
from web.kept_contexts import Kept, left_as_new
from web.webtools import (
    ADMIN_EMAIL,
    AXE_PATH,
    CHROMIUM,
    CHROMIUM_ARGS,
    OFFICER_EMAIL,
    PASSWORD,
    STUDY_SEATS,
    sign_in,
)


@pytest.fixture
def officer(session: Session) -> User:
    """An officer account."""
    return create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")


@pytest.fixture
def admin(session: Session) -> User:
    """An administrator account."""
    return create_user(session, email=ADMIN_EMAIL, password=PASSWORD, role="admin")


@pytest.fixture
def web(client: TestClient, officer: User) -> TestClient:
    """A TestClient signed in as the officer."""
    assert sign_in(client, OFFICER_EMAIL).status_code == 303
    return client


@pytest.fixture
def admin_web(client: TestClient, admin: User) -> TestClient:
    """A TestClient signed in as the administrator."""
    assert sign_in(client, ADMIN_EMAIL).status_code == 303
    return client


@pytest.fixture
def study_vehicle(session: Session) -> Vehicle:
    """The study's vehicle BDG 252 QH: wheelbase 2.000 m, driver at 0.9303 m, three passengers."""
    return register_vehicle(
        session,
        registration_number="BDG 252 QH",
        make="Bajaj",
        model="RE",
        model_year=2012,
        wheelbase_m=Decimal("2.000"),
        seats=STUDY_SEATS,
    )


# ---- the browser tests: the real app under uvicorn, Debian's Chromium --------------------------


@pytest.fixture(scope="session")
def live_server(database_url: str) -> Iterator[str]:
    """The app served by uvicorn in a thread on 127.0.0.1 and a free port, on the test database."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(create_app(), log_level="warning", access_log=False))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    deadline = time.monotonic() + 10
    while not server.started and time.monotonic() < deadline:
        time.sleep(0.02)
    assert server.started, "uvicorn did not start"
    yield f"http://127.0.0.1:{port}"
    server.should_exit = True
    thread.join(timeout=10)
    sock.close()


@pytest.fixture(scope="session")
def chromium() -> str:
    """Debian's Chromium; missing, every browser test is skipped saying so (a failure on CI)."""
    if not os.access(CHROMIUM, os.X_OK):
        tool_missing(
            f"Chromium ({CHROMIUM})",
            "apt-get install chromium-headless-shell (or chromium), or set TRIKECERT_CHROMIUM",
        )
    return CHROMIUM


@pytest.fixture(scope="session")
def browser_type_launch_args(browser_type_launch_args: dict[str, Any], chromium: str) -> dict[str, Any]:
    """Launch Debian's Chromium, never a downloaded browser."""
    return {**browser_type_launch_args, "executable_path": chromium, "args": CHROMIUM_ARGS, "headless": True}


@pytest.fixture(scope="session")
def browser_context_args(browser_context_args: dict[str, Any], live_server: str) -> dict[str, Any]:
    """Every page opens on the live server, 1280 px wide."""
    return {**browser_context_args, "base_url": live_server, "viewport": {"width": 1280, "height": 900}}


@pytest.fixture
def axe_script() -> Path:
    """axe.min.js, the only way a test reaches axe-core: missing, the test is skipped saying so (a
    failure on CI)."""
    if not AXE_PATH.is_file():
        tool_missing(f"axe-core ({AXE_PATH})", "run `npm ci` at the top of the repository")
    return AXE_PATH


@pytest.fixture(scope="session")
def kept_contexts(browser: Browser) -> Iterator[dict[str, Kept]]:
    """The run's kept contexts, one per set of options (`kept_context`)."""
    kept: dict[str, Kept] = {}
    yield kept
    for each in kept.values():
        each.context.close()


@pytest.fixture
def kept_context(
    browser: Browser,
    browser_context_args: dict[str, Any],
    live_server: str,
    kept_contexts: dict[str, Kept],
) -> Iterator[Callable[..., BrowserContext]]:
    """A context with these options, made once per run, and left after each test as a new one starts
    (tests/web/kept_contexts.py)."""
    taken: list[Kept] = []

    def take(**options: Any) -> BrowserContext:
        arguments = {**browser_context_args, **options}
        key = repr(sorted(arguments.items()))
        if key not in kept_contexts:
            context = browser.new_context(**arguments)
            kept_contexts[key] = Kept(context, context.new_page())
        kept = kept_contexts[key]
        if kept not in taken:
            taken.append(kept)
        return kept.context

    yield take
    for kept in taken:
        left_as_new(kept, live_server)


@pytest.fixture
def context(kept_context: Callable[..., BrowserContext]) -> BrowserContext:
    """pytest-playwright's context for `page`: a kept one (`kept_context`)."""
    return kept_context()


@pytest.fixture
def audit_page(kept_context: Callable[..., BrowserContext]) -> Page:
    """A page that may inject axe-core despite the pages' Content-Security-Policy."""
    return kept_context(bypass_csp=True).new_page()


@pytest.fixture
def required(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """TRIKECERT_MFA=required, as in production, for the app and the command line alike."""
    monkeypatch.setenv("TRIKECERT_MFA", "required")
    config.get_settings.cache_clear()
    yield
    monkeypatch.delenv("TRIKECERT_MFA")
    config.get_settings.cache_clear()


@pytest.fixture
def station(session: Session) -> Station:
    """A station with a scale on record."""
    station, _key = create_station(
        session,
        name="Ojota weighbridge",
        details=StationDetails(
            location="Ojota, Lagos",
            calibration_certificate="SON/CAL/2026/0001",
            calibration_valid_until=date(2099, 1, 31),
            capacity_kg=Decimal(3000),
            division_kg=Decimal(1),
        ),
    )
    return station
