"""Keys no station holds, throttled per client address: beyond the limit 429 with Retry-After; other
addresses keep their 401; a valid key passes from every address, the throttled one included (a
station behind the same carrier-grade NAT keeps working)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS

from app import config
from app.api import address_limits
from app.api.address_limits import AddressWindows
from app.api.windows import RateLimit
from app.main import create_app
from app.stations.service import create_station

INSPECTIONS = "/api/v1/inspections"
BAD = {"Authorization": "Bearer tks_not-a-key-of-any-station"}


@pytest.fixture(autouse=True)
def still_clock(monkeypatch: pytest.MonkeyPatch) -> None:
    """The windows' clock held still: no window turns in the middle of a test."""
    monkeypatch.setattr(address_limits, "clock", lambda: 1_800_000_010.0)


@pytest.fixture
def app(engine: object, monkeypatch: pytest.MonkeyPatch) -> Iterator[FastAPI]:
    """A fresh application (its own counts) allowing 3 unknown keys per address."""
    monkeypatch.setenv("TRIKECERT_BAD_KEY_LIMIT", "3")
    config.get_settings.cache_clear()
    yield create_app()
    monkeypatch.undo()
    config.get_settings.cache_clear()


def from_address(app: FastAPI, address: str) -> TestClient:
    """A client on `app` whose requests come from `address`."""
    return TestClient(app, raise_server_exceptions=False, client=(address, 40000))


def test_beyond_the_limit_an_address_sending_unknown_keys_gets_429(app: FastAPI) -> None:
    prober = from_address(app, "198.51.100.7")

    statuses = [prober.get(INSPECTIONS, headers=BAD).status_code for _ in range(3)]
    refused = prober.get(INSPECTIONS, headers=BAD)

    assert statuses == [401, 401, 401]
    assert refused.status_code == 429
    assert 1 <= int(refused.headers["Retry-After"]) <= 300
    assert refused.json()["errors"] == [
        {"field": "Authorization", "rule": "rate_limit", "message": refused.json()["detail"]}
    ]
    assert "more than 3 requests with a key no station holds" in refused.json()["detail"]
    submission = prober.post(INSPECTIONS, json={"registration_number": "BDG 252 QH"}, headers=BAD)
    assert submission.status_code == 429, "the submission's own look-up is throttled the same way"
    assert "Retry-After" in submission.headers


def test_other_addresses_keep_their_401_and_valid_keys_pass_everywhere(
    app: FastAPI, session: Session
) -> None:
    _station, key = create_station(session, name="Station A")
    signed = {"Authorization": f"Bearer {key}"}
    prober = from_address(app, "198.51.100.7")
    for _ in range(5):
        prober.get(INSPECTIONS, headers=BAD)
    assert prober.get(INSPECTIONS, headers=BAD).status_code == 429

    assert from_address(app, "198.51.100.8").get(INSPECTIONS, headers=BAD).status_code == 401
    assert from_address(app, "198.51.100.8").get(INSPECTIONS, headers=signed).status_code == 200
    assert prober.get(INSPECTIONS, headers=signed).status_code == 200, "a station behind the same address"
    weighed = prober.post(
        INSPECTIONS, json={"registration_number": "BDG 252 QH", "readings": STUDY_READINGS}, headers=signed
    )
    assert weighed.status_code == 404, "the station's submission is answered (its vehicle is unknown)"


def test_a_missing_key_is_not_counted_and_an_ipv6_subscriber_counts_as_its_64(app: FastAPI) -> None:
    one = from_address(app, "2001:db8:5:1::1")
    same_network = from_address(app, "2001:db8:5:1:ffff::2")
    next_network = from_address(app, "2001:db8:5:2::1")
    assert {one.get(INSPECTIONS).status_code for _ in range(5)} == {401}, "no key: plain 401, never counted"

    assert [one.get(INSPECTIONS, headers=BAD).status_code for _ in range(2)] == [401, 401]
    assert same_network.get(INSPECTIONS, headers=BAD).status_code == 401
    assert same_network.get(INSPECTIONS, headers=BAD).status_code == 429
    assert next_network.get(INSPECTIONS, headers=BAD).status_code == 401


def test_the_window_reopens_and_retry_after_counts_down() -> None:
    windows = AddressWindows(RateLimit(limit=2, window_seconds=60))
    assert windows.count("a", now=1200.0) is None
    assert windows.count("a", now=1210.0) is None
    assert windows.count("a", now=1249.5) == 11
    assert windows.count("b", now=1249.5) is None
    assert windows.count("a", now=1260.0) is None, "a new window"
    assert windows.count("a", now=1259.9) is None, "a late request counts in the newer window"
    assert windows.count("a", now=1261.0) == 59


def test_memory_stays_bounded_and_a_limit_of_zero_is_no_limit() -> None:
    windows = AddressWindows(RateLimit(limit=1, window_seconds=60), max_addresses=2)
    for address in ("a", "b", "c", "c", "c"):
        windows.count(address, now=0.0)
    assert windows.count("a", now=1.0) == 59
    assert windows.count("c", now=1.0) is None, "beyond the addresses kept, new ones are not counted"
    off = AddressWindows(RateLimit(limit=0, window_seconds=60))
    assert {off.count("a", now=0.0) for _ in range(5)} == {None}
