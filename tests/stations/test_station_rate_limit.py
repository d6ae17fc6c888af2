"""The rate limit per station key: beyond it, 429 with Retry-After; each key has its own window; the
window reopens; 0 turns it off. (Across worker processes: test_station_concurrency.py.)"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app import config
from app.api.windows import RateLimit
from app.stations.rate_limit import RateLimited, authenticate_and_count
from app.stations.service import create_station

INSPECTIONS = "/api/v1/inspections"


@pytest.fixture
def limit_of_three(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    monkeypatch.setenv("TRIKECERT_STATION_RATE_LIMIT", "3")
    config.get_settings.cache_clear()
    yield
    monkeypatch.undo()
    config.get_settings.cache_clear()


@pytest.mark.usefixtures("limit_of_three")
def test_beyond_the_limit_a_station_gets_429_with_retry_after(client: TestClient, session: Session) -> None:
    _a, key = create_station(session, name="Station A")
    _b, other = create_station(session, name="Station B")
    signed = {"Authorization": f"Bearer {key}"}

    statuses = [client.get(INSPECTIONS, headers=signed).status_code for _ in range(4)]
    refused = client.post(INSPECTIONS, json={}, headers=signed)

    assert statuses == [200, 200, 200, 429]
    assert refused.status_code == 429, "counted before the body is looked at"
    assert 1 <= int(refused.headers["Retry-After"]) <= 60
    assert refused.json()["errors"] == [
        {"field": "Authorization", "rule": "rate_limit", "message": refused.json()["detail"]}
    ]
    assert "more than 3 requests in 60 s" in refused.json()["detail"]
    assert client.get(INSPECTIONS, headers={"Authorization": f"Bearer {other}"}).status_code == 200
    assert client.get(INSPECTIONS).status_code == 401, "an unsigned request is refused, not counted"


def test_the_window_reopens_and_retry_after_counts_down(session: Session) -> None:
    station, key = create_station(session, name="Station A")
    limit = RateLimit(limit=2, window_seconds=60)
    for now in (1200.0, 1210.0):
        assert authenticate_and_count(session, key, limit=limit, now=now) is station
    with pytest.raises(RateLimited) as refused:
        authenticate_and_count(session, key, limit=limit, now=1249.5)
    assert refused.value.retry_after == 11
    assert authenticate_and_count(session, key, limit=limit, now=1260.0) is station  # a new window


def test_a_late_request_counts_in_the_newer_window(session: Session) -> None:
    _station, key = create_station(session, name="Station A")
    limit = RateLimit(limit=1, window_seconds=60)
    authenticate_and_count(session, key, limit=limit, now=1265.0)
    with pytest.raises(RateLimited):  # timed by a worker just before the window turned
        authenticate_and_count(session, key, limit=limit, now=1259.9)


def test_a_limit_of_zero_is_no_limit(session: Session) -> None:
    station, key = create_station(session, name="Station A")
    for _ in range(5):
        assert authenticate_and_count(session, key, limit=RateLimit(0, 60)) is station
