"""Security headers on every kind of answer, and /metrics behind its bearer token (issue 10, item 7).

Through the app in process; tests/ops/test_ops_headers_served.py checks what only a served
process shows (the Server header, X-Forwarded-Proto from a trusted proxy or not).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import Engine
from study_data import STUDY_VEHICLE

from app.config import Settings, get_settings
from app.main import create_app

TOKEN = "scrape-token-0123456789abcdef"

# (method, path, status): one of each kind of answer the service gives.
ANSWERS = [
    ("GET", "/login", 200),  # a page
    ("GET", "/", 303),  # a page's redirect to sign in
    ("GET", "/inspections/1", 303),
    ("GET", "/no-such-page", 404),  # a page's 404 (a browser asks for HTML)
    ("GET", "/api/v1/vehicles/BDG252QH", 200),  # the API
    ("POST", "/api/v1/vehicles", 422),  # an API refusal
    ("GET", "/api/v1/no-such-thing", 404),  # the API's 404
    ("GET", "/api/v1/vehicles/NOPE1", 404),
    ("GET", "/healthz", 200),
    ("GET", "/readyz", 200),
    ("GET", "/metrics", 200),
    ("GET", "/docs", 200),
    ("GET", "/redoc", 200),
    ("GET", "/docs/assets/swagger-ui-bundle.js", 200),
    ("GET", "/openapi.json", 200),
    ("GET", "/static/app.css", 200),
    ("GET", "/static/missing.css", 404),
    ("GET", "/.well-known/trikecert-keys.json", 200),
    ("GET", "/verify", 200),
    ("GET", "/boom", 500),  # an unhandled error, answered by Starlette's last-resort handler
]


@pytest.fixture
def every_answer(engine: Engine, station_key: str) -> Iterator[Callable[[str], TestClient]]:
    """A client on an app with one route that fails, the study's vehicle registered; by base URL."""
    clients: list[TestClient] = []

    def make(base_url: str) -> TestClient:
        app = create_app()

        @app.get("/boom")
        def boom() -> None:
            raise RuntimeError("a bug")

        client = TestClient(app, base_url=base_url, raise_server_exceptions=False, follow_redirects=False)
        client.headers["Authorization"] = f"Bearer {station_key}"
        clients.append(client)
        return client

    setup = make("http://testserver")
    assert setup.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    yield make
    for client in clients:
        client.close()


def _answer(client: TestClient, method: str, path: str) -> tuple[int, dict[str, str]]:
    accept = "text/html" if not path.startswith(("/api/", "/metrics", "/healthz", "/readyz")) else "*/*"
    response = client.request(method, path, json={} if method == "POST" else None, headers={"Accept": accept})
    return response.status_code, dict(response.headers)


def test_every_kind_of_answer_says_nosniff_and_no_server_over_http(
    every_answer: Callable[[str], TestClient],
) -> None:
    client = every_answer("http://testserver")
    for method, path, status in ANSWERS:
        got, headers = _answer(client, method, path)
        assert got == status, (method, path, got)
        assert headers.get("x-content-type-options") == "nosniff", (method, path)
        assert "strict-transport-security" not in headers, (method, path)
        assert "server" not in headers, (method, path)


def test_every_kind_of_answer_over_https_also_says_strict_transport_security(
    every_answer: Callable[[str], TestClient],
) -> None:
    client = every_answer("https://testserver")
    for method, path, status in ANSWERS:
        got, headers = _answer(client, method, path)
        assert got == status, (method, path, got)
        assert headers.get("x-content-type-options") == "nosniff", (method, path)
        assert headers.get("strict-transport-security") == "max-age=31536000", (method, path)


def test_an_https_claim_from_the_client_itself_does_not_earn_hsts(client: TestClient) -> None:
    # In process there is no trusted proxy: the header is only a header.
    response = client.get("/healthz", headers={"X-Forwarded-Proto": "https"})
    assert response.status_code == 200
    assert "strict-transport-security" not in response.headers


# ---- /metrics -------------------------------------------------------------------------------------


@pytest.fixture
def metrics_settings(monkeypatch: pytest.MonkeyPatch) -> Callable[..., None]:
    """Serve /metrics under settings changed as given (environment, metrics_token)."""

    def use(**changes: object) -> None:
        changed = get_settings().model_copy(update=changes)
        assert isinstance(changed, Settings)
        monkeypatch.setattr("app.ops.metrics.get_settings", lambda: changed)

    return use


def test_metrics_with_a_token_refuse_a_scrape_without_it_or_with_another(
    client: TestClient, metrics_settings: Callable[..., None]
) -> None:
    from pydantic import SecretStr

    metrics_settings(metrics_token=SecretStr(TOKEN))
    for headers in ({}, {"Authorization": "Bearer wrong-token"}, {"Authorization": TOKEN}):
        refused = client.get("/metrics", headers=headers)
        assert refused.status_code == 401, headers
        assert refused.headers["www-authenticate"].startswith("Bearer")
        assert refused.json()["errors"][0]["field"] == "Authorization"
        assert "trikecert_" not in refused.text
    scraped = client.get("/metrics", headers={"Authorization": f"Bearer {TOKEN}"})
    assert scraped.status_code == 200
    assert "trikecert_inspections" in scraped.text


def test_metrics_without_a_token_are_off_in_production(
    client: TestClient, metrics_settings: Callable[..., None]
) -> None:
    metrics_settings(environment="production", metrics_token=None)
    response = client.get("/metrics", headers={"Authorization": f"Bearer {TOKEN}"})
    assert response.status_code == 404
    assert "trikecert_" not in response.text


def test_metrics_without_a_token_stay_open_in_development(
    client: TestClient, metrics_settings: Callable[..., None]
) -> None:
    metrics_settings(environment="development", metrics_token=None)
    response = client.get("/metrics")
    assert response.status_code == 200
    assert "trikecert_http_requests_total" in response.text


def test_a_metrics_token_shorter_than_16_characters_is_refused_at_start() -> None:
    with pytest.raises(ValueError, match="metrics_token"):
        Settings(metrics_token="short")


def test_a_trusted_proxy_that_is_no_address_is_refused_at_start() -> None:
    with pytest.raises(ValueError, match=r"TRIKECERT_FORWARDED_ALLOW_IPS: 'proxy\.local'"):
        Settings(forwarded_allow_ips="10.0.0.0/8, proxy.local")
    assert (
        Settings(forwarded_allow_ips=" 10.0.0.0/8 ,127.0.0.1").forwarded_allow_ips == "10.0.0.0/8,127.0.0.1"
    )
