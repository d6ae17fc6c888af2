"""GET /.well-known/trikecert-trust: the signed bundle made from the records, a strong ETag and 304,
gzip when asked, no-cache; a revocation is in the very next answer."""

from __future__ import annotations

import gzip
from typing import Any

import pytest
from access_lines import access_lines
from fastapi.testclient import TestClient
from offline_cases import COMPLIANT, COMPLIANT_READINGS, _issue, trust_anchor
from prometheus_client import REGISTRY
from sqlalchemy.orm import Session

from app import config
from app.api import address_limits
from app.certificates.actors import Actor
from app.certificates.service import revoke_certificate
from app.main import create_app
from app.trust.bundle import open_bundle
from app.trust.numbers import parse_number

PATH = "/.well-known/trikecert-trust"


def _open(text: str) -> object:
    signer = trust_anchor()
    return open_bundle(text, trusted={signer.kid: signer.public_jwk()["x"]})


def test_the_bundle_is_signed_cached_and_compressed(api: TestClient) -> None:
    paper = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    plain = api.get(PATH, headers={"Accept-Encoding": "identity"})
    assert plain.status_code == 200
    assert plain.headers["content-type"] == "application/jose"
    assert plain.headers["cache-control"] == "no-cache"
    assert "content-encoding" not in plain.headers
    etag = plain.headers["etag"]
    assert etag.startswith('"')
    assert not etag.startswith("W/")
    opened = _open(plain.text)
    bundle = opened.bundle  # type: ignore[attr-defined]
    digits = int(parse_number(paper["number"]).digits)
    (key,) = bundle.keys
    assert (key.kid, key.status, key.numbers) == (paper["key_id"], "active", (digits, None))
    assert bundle.issuer == "127.0.0.1:8000"
    assert bundle.revoked == {}
    assert bundle.max_age == 72 * 3600

    again = api.get(PATH, headers={"Accept-Encoding": "identity", "If-None-Match": etag})
    assert again.status_code == 304
    assert again.content == b""
    assert again.headers["etag"] == etag

    zipped = api.get(PATH, headers={"Accept-Encoding": "gzip"})
    assert zipped.headers["content-encoding"] == "gzip"
    assert zipped.text == plain.text  # the client unzipped it
    assert zipped.headers["etag"] != etag  # another representation, another strong tag
    assert len(gzip.compress(plain.content)) < len(plain.content)


def test_a_revocation_is_in_the_very_next_bundle(api: TestClient, session: Session) -> None:
    paper = _issue(api, "KTU 418 XA", COMPLIANT, COMPLIANT_READINGS)
    first = api.get(PATH)
    revoke_certificate(session, number=paper["number"], actor=Actor.of_cli(), reason="plate forged")
    second = api.get(PATH, headers={"If-None-Match": first.headers["etag"]})
    assert second.status_code == 200
    before, after = _open(first.text).bundle, _open(second.text).bundle  # type: ignore[attr-defined]
    digits = int(parse_number(paper["number"]).digits)
    assert digits not in before.revoked
    assert after.revoked[digits][1] == "R"
    assert after.seq > before.seq


def _comparable(response: Any) -> tuple[int, bytes, list[tuple[str, str]]]:
    per_request = ("date", "x-request-id")
    headers = [(n, v) for n, v in response.headers.multi_items() if n not in per_request]
    return response.status_code, response.content, headers


def test_a_kept_bundle_is_served_before_the_router_exactly_as_the_route_serves_it(
    api: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    paper = _issue(api, "KTU 419 XA", COMPLIANT, COMPLIANT_READINGS)
    asks = [{"Accept-Encoding": "identity"}, {"Accept-Encoding": "gzip"}]
    monkeypatch.setattr("app.certificates.kept_door.is_bundle_kept", lambda _settings: False)
    by_route = [api.get(PATH, headers=headers) for headers in asks]
    tags = [answer.headers["etag"] for answer in by_route]
    asks += [{**headers, "If-None-Match": tag} for headers, tag in zip(asks, tags, strict=True)]
    by_route += [api.get(PATH, headers=headers) for headers in asks[2:]]
    monkeypatch.undo()

    def no_route(*_: object, **__: object) -> object:
        raise AssertionError("the route was called for the kept bundle")

    monkeypatch.setattr("app.certificates.public.served_bundle", no_route)
    served = [api.get(PATH, headers=headers) for headers in asks]
    assert [_comparable(answer) for answer in served] == [_comparable(answer) for answer in by_route]
    assert [answer.status_code for answer in served] == [200, 200, 304, 304]

    monkeypatch.undo()
    revoke_certificate(session, number=paper["number"], actor=Actor.of_cli(), reason="plate forged")
    session.commit()
    after = api.get(PATH, headers=asks[2])  # the next request: a new bundle, not the 304
    assert after.status_code == 200
    assert after.headers["etag"] != by_route[0].headers["etag"]


def test_the_304_ahead_of_the_stack_is_logged_counted_and_limited_once_like_any_answer(
    api: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    _issue(api, "KTU 420 XA", COMPLIANT, COMPLIANT_READINGS)
    monkeypatch.setattr(address_limits, "clock", lambda: 1_800_000_010.0)  # no window turns mid-test
    monkeypatch.setenv("TRIKECERT_PUBLIC_RATE_LIMIT", "4")
    config.get_settings.cache_clear()
    checker = TestClient(create_app(), base_url="https://testserver")  # counts of its own; over https
    try:
        with access_lines() as lines:
            first = checker.get(PATH)
            tag = first.headers["etag"]
            asked = {"If-None-Match": tag, "X-Request-ID": "checker-1"}
            ahead = checker.get(PATH, headers=asked)  # no query: answered ahead of the stack
            by_route = checker.get(f"{PATH}?via=route", headers=asked)
            other_tag = checker.get(PATH, headers={"If-None-Match": '"another"'})
            over = checker.get(PATH, headers={"If-None-Match": tag})
    finally:
        config.get_settings.cache_clear()

    # Each request counted once against the limit of 4, wherever it was answered.
    statuses = [r.status_code for r in (first, ahead, by_route, other_tag, over)]
    assert statuses == [200, 304, 304, 200, 429]
    assert ahead.headers["strict-transport-security"] == "max-age=31536000"
    assert list(ahead.headers.multi_items()) == list(by_route.headers.multi_items())
    assert [(line["handler"], line["status"]) for line in lines] == [
        ("trust_bundle", 200),
        ("trust_bundle", 304),
        ("trust_bundle", 304),
        ("trust_bundle", 200),
        ("unmatched", 429),
    ]
    assert lines[1]["request_id"] == "checker-1"
    counted = REGISTRY.get_sample_value(
        "trikecert_http_requests_total", {"method": "GET", "handler": "trust_bundle", "status": "304"}
    )
    assert counted is not None
    assert counted >= 2
