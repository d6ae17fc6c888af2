"""What only a served process shows (issue 10, item 7): `trikecert serve` sends no Server header, and
believes X-Forwarded-Proto: https (answering with HSTS) only from a proxy named in
TRIKECERT_FORWARDED_ALLOW_IPS; /metrics asks for its bearer token."""

from __future__ import annotations

import os
import subprocess
import sys
import urllib.error
import urllib.request
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from http.client import HTTPResponse
from pathlib import Path

import pytest
from served import free_port, wait_until_ready
from sqlalchemy import Engine

BIN = Path(sys.executable).parent
TOKEN = "served-scrape-token-0123456789"
HTTPS = {"X-Forwarded-Proto": "https"}


@contextmanager
def _serving(database_url: str, **settings: str) -> Iterator[str]:
    """`trikecert serve` on the test database with these TRIKECERT_ settings; yields its base URL."""
    env = dict(os.environ, TRIKECERT_DATABASE_URL=database_url)
    env.pop("FORWARDED_ALLOW_IPS", None)  # uvicorn's own variable must not decide for us
    env.update({f"TRIKECERT_{name.upper()}": value for name, value in settings.items()})
    port = free_port()
    server = subprocess.Popen(
        [BIN / "trikecert", "serve", "--no-migrate", "--port", str(port)],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        wait_until_ready(f"{base}/healthz", server)
        yield base
    finally:
        server.terminate()
        server.wait(timeout=30)


def _get(
    url: str, headers: dict[str, str] | None = None
) -> tuple[int, HTTPResponse | urllib.error.HTTPError]:
    request = urllib.request.Request(url, headers=headers or {})
    try:
        with urllib.request.urlopen(request, timeout=10) as response:
            response.read()
            return response.status, response
    except urllib.error.HTTPError as error:
        error.read()
        return error.code, error


@pytest.fixture
def serve(engine: Engine, database_url: str) -> Callable[..., AbstractContextManager[str]]:
    """Start a served process with the settings given."""
    return lambda **settings: _serving(database_url, **settings)


@pytest.fixture(scope="module")
def trusting_no_proxy(database_url: str) -> Iterator[str]:
    """One served process for the tests that read it only: no proxy named, metrics behind TOKEN."""
    with _serving(database_url, metrics_token=TOKEN) as base:
        yield base


PATHS = (
    "/healthz",
    "/api/v1/vehicles/BDG252QH",
    "/login",
    "/docs",
    "/openapi.json",
    "/static/app.css",
    "/nope",
)


def test_a_served_answer_has_no_server_header_and_an_untrusted_https_claim_earns_no_hsts(
    trusting_no_proxy: str,
) -> None:
    for path in PATHS:
        status, response = _get(f"{trusting_no_proxy}{path}", HTTPS)
        assert status in (200, 401, 404), (path, status)
        assert response.headers.get("Server") is None, path
        assert response.headers["X-Content-Type-Options"] == "nosniff", path
        assert response.headers.get("Strict-Transport-Security") is None, path


def test_behind_a_trusted_proxy_an_https_request_gets_hsts_and_a_plain_one_does_not(
    serve: Callable[..., AbstractContextManager[str]],
) -> None:
    with serve(forwarded_allow_ips="127.0.0.1") as base:
        for path in PATHS:
            _status, secure = _get(f"{base}{path}", HTTPS)
            assert secure.headers["Strict-Transport-Security"] == "max-age=31536000", path
            assert secure.headers.get("Server") is None, path
            _status, plain = _get(f"{base}{path}", {"X-Forwarded-Proto": "http"})
            assert plain.headers.get("Strict-Transport-Security") is None, path


def test_a_proxy_on_another_address_is_not_believed(
    serve: Callable[..., AbstractContextManager[str]],
) -> None:
    with serve(forwarded_allow_ips="192.0.2.0/24") as base:
        _status, response = _get(f"{base}/healthz", HTTPS)
        assert response.headers.get("Strict-Transport-Security") is None


def test_served_metrics_ask_for_the_bearer_token(trusting_no_proxy: str) -> None:
    base = trusting_no_proxy
    status, response = _get(f"{base}/metrics")
    assert status == 401
    assert response.headers["WWW-Authenticate"].startswith("Bearer")
    status, _response = _get(f"{base}/metrics", {"Authorization": "Bearer not-the-token"})
    assert status == 401
    status, _response = _get(f"{base}/metrics", {"Authorization": f"Bearer {TOKEN}"})
    assert status == 200
