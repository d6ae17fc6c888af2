"""The per-address limit of the public verification: an enumeration of certificate numbers from one
address is refused with 429 and Retry-After (a page for a browser, the API's error body for a
program), other addresses are not affected, and a police post's normal use never meets the default."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from certificate_helpers import study_certificate
from fastapi import FastAPI
from fastapi.testclient import TestClient

from app import config
from app.api import address_limits
from app.main import create_app
from app.trust.numbers import CertificateNumber, parse_number

JSON = {"Accept": "application/json"}
HTML = {"Accept": "text/html,application/xhtml+xml,*/*;q=0.8"}


@pytest.fixture(autouse=True)
def still_clock(monkeypatch: pytest.MonkeyPatch) -> None:
    """The windows' clock held still: no window turns in the middle of a test."""
    monkeypatch.setattr(address_limits, "clock", lambda: 1_800_000_010.0)


def limit_of(monkeypatch: pytest.MonkeyPatch, requests: int) -> None:
    monkeypatch.setenv("TRIKECERT_PUBLIC_RATE_LIMIT", str(requests))
    config.get_settings.cache_clear()


@pytest.fixture
def issued(api: TestClient) -> dict[str, Any]:
    body = study_certificate(api)
    api.headers.pop("Authorization")
    return body


@pytest.fixture
def app(issued: dict[str, Any]) -> Iterator[FastAPI]:
    """A fresh application (its own counts), once the certificate is issued."""
    yield create_app()
    config.get_settings.cache_clear()


def from_address(app: FastAPI, address: str) -> TestClient:
    """A client on `app` whose requests come from `address`."""
    return TestClient(app, raise_server_exceptions=False, client=(address, 40000))


def test_an_enumeration_of_numbers_from_one_address_is_refused_beyond_the_limit(
    issued: dict[str, Any], app: FastAPI, monkeypatch: pytest.MonkeyPatch
) -> None:
    limit_of(monkeypatch, 20)
    enumerator = from_address(app, "198.51.100.7")
    first = parse_number(issued["number"])
    numbers = [str(CertificateNumber(first.year, first.sequence + n)) for n in range(60)]

    answers = [enumerator.get(f"/api/v1/verify/{number}") for number in numbers]

    assert [a.status_code for a in answers[:20]] == [200] + [404] * 19
    assert {a.status_code for a in answers[20:]} == {429}
    refused = answers[20]
    assert 1 <= int(refused.headers["Retry-After"]) <= 60
    assert refused.json() == {
        "detail": refused.json()["detail"],
        "errors": [{"field": "client", "rule": "rate_limit", "message": refused.json()["detail"]}],
    }
    assert "more than 20 verification requests came from this address in 60 s" in refused.json()["detail"]
    assert issued["registration_number"] not in enumerator.get(f"/api/v1/verify/{numbers[0]}").text

    police_post = from_address(app, "198.51.100.8")
    answer = police_post.get(f"/api/v1/verify/{issued['number']}")
    assert answer.status_code == 200, "another address is not affected"
    assert answer.json()["registration_number"] == issued["registration_number"]


def test_a_browser_gets_a_page_that_says_when_to_try_again(
    issued: dict[str, Any], app: FastAPI, monkeypatch: pytest.MonkeyPatch
) -> None:
    limit_of(monkeypatch, 2)
    browser = from_address(app, "198.51.100.9")
    page = f"/verify/{issued['number']}"
    assert [browser.get(page, headers=HTML).status_code for _ in range(2)] == [200, 200]

    refused = browser.get(page, headers=HTML)

    assert refused.status_code == 429
    assert refused.headers["content-type"].startswith("text/html")
    wait = refused.headers["Retry-After"]
    assert "Please wait a moment" in refused.text
    assert f"Wait {wait} seconds, then check the certificate again." in refused.text
    assert f'href="{page}"' in refused.text, "the page offers to check the same certificate again"
    assert issued["registration_number"] not in refused.text
    asked_json = browser.get(page, headers=JSON)
    assert asked_json.status_code == 429
    assert asked_json.json()["errors"][0]["rule"] == "rate_limit"


def test_the_qr_address_and_the_published_keys_count_too(
    issued: dict[str, Any], app: FastAPI, monkeypatch: pytest.MonkeyPatch
) -> None:
    limit_of(monkeypatch, 3)
    client = from_address(app, "2001:db8:7:1::10")
    neighbour = from_address(app, "2001:db8:7:1::99")  # the same /64: the same subscriber
    elsewhere = from_address(app, "2001:db8:7:2::10")

    assert client.get("/.well-known/trikecert-keys.json").status_code == 200
    assert client.get(f"/V/{issued['number']}", follow_redirects=False).status_code != 429
    assert neighbour.get("/.well-known/trikecert-keys.json").status_code == 200
    refused = client.get("/.well-known/trikecert-keys.json")

    assert refused.status_code == 429
    assert refused.json()["errors"][0]["field"] == "client"
    assert elsewhere.get("/.well-known/trikecert-keys.json").status_code == 200
    assert client.get("/.well-known/trikecert-trust").status_code == 429  # the trust bundle too
    assert client.get("/healthz").status_code == 200, "other doors are not counted"


def test_a_police_post_checking_a_vehicle_every_two_seconds_never_meets_the_default(
    issued: dict[str, Any], app: FastAPI
) -> None:
    post = from_address(app, "198.51.100.20")
    number = issued["number"]
    # A minute of checks at one post: each the page, then its JSON, and the keys now and then.
    statuses = {post.get(f"/verify/{number}", headers=HTML).status_code for _ in range(30)}
    statuses |= {post.get(f"/api/v1/verify/{number}").status_code for _ in range(30)}
    statuses |= {post.get("/.well-known/trikecert-keys.json").status_code for _ in range(5)}
    assert statuses == {200}
    assert config.get_settings().public_rate_limit >= 4 * 65, "four such posts behind one address too"


def test_a_limit_of_zero_is_no_limit(
    issued: dict[str, Any], app: FastAPI, monkeypatch: pytest.MonkeyPatch
) -> None:
    limit_of(monkeypatch, 0)
    client = from_address(app, "198.51.100.30")
    assert {client.get(f"/api/v1/verify/{issued['number']}").status_code for _ in range(10)} == {200}
