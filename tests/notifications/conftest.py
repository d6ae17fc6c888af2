"""Fixtures of the feature-phone tests: the gateway's callbacks switched on, and a vehicle for each
state a document can be in (certified, refused, revoked, superseded, expired, none)."""

from __future__ import annotations

from collections.abc import Iterator
from datetime import timedelta

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app import config
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, revoke_certificate
from app.db import utcnow
from notifications.phone_helpers import TOKEN, State, certify, trike, weigh


@pytest.fixture
def gateway_on(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """The callbacks switched on with the test's token."""
    monkeypatch.setenv("TRIKECERT_GATEWAY_CALLBACK_TOKEN", TOKEN)
    config.get_settings.cache_clear()
    yield
    monkeypatch.delenv("TRIKECERT_GATEWAY_CALLBACK_TOKEN")
    config.get_settings.cache_clear()


@pytest.fixture
def states(api: TestClient, session: Session) -> list[State]:
    """One vehicle or number for each state a phone can find."""
    certified = certify(api, weigh(api, "KTU 417 XA"))
    certify(api, weigh(api, "BDG 252 QH", stable=False))
    revoked = certify(api, weigh(api, "LAG 100 RV"))
    revoke_certificate(session, number=revoked, actor=Actor.of_cli(), reason="forged readings")
    old = certify(api, weigh(api, "ABJ 200 SP"))
    newer = certify(api, weigh(api, "ABJ 200 SP", register=False))
    expired_inspection = weigh(api, "KAN 300 EX")
    issue_certificate(
        session,
        inspection_id=expired_inspection,
        actor=Actor.of_cli(),
        settings=config.get_settings(),
        now=utcnow() - timedelta(days=400),
    )
    assert api.post("/api/v1/vehicles", json=trike("OYO 400 NN")).status_code == 201
    return [
        State(
            "certified",
            "ktu-417-xa",
            (
                "KTU 417 XA: VALID CERTIFICATE",
                "Certified for the driver and up to one passenger",
                "Valid until",
            ),
        ),
        State("certified by number", certified.lower(), ("KTU 417 XA: VALID CERTIFICATE", "Valid until")),
        State("refused", "BDG252QH", ("BDG 252 QH: NOT CERTIFIED: refusal", "This refusal stands until")),
        State(
            "revoked",
            "LAG 100 RV",
            ("LAG 100 RV: REVOKED on", "This certificate was withdrawn: it certifies nothing"),
        ),
        State("superseded", old, ("ABJ 200 SP: SUPERSEDED on", f"Only certificate {newer} counts")),
        State("newer of superseded", "ABJ200SP", ("ABJ 200 SP: VALID CERTIFICATE",)),
        State("expired", "kan 300 ex", ("KAN 300 EX: EXPIRED on", "the vehicle must be weighed again")),
        State("none", "OYO 400 NN", ("OYO 400 NN: NOT CERTIFIED", "No certificate or refusal is on record")),
        State("unknown plate", "ZZZ 999 ZZ", ("No keke ZZZ 999 ZZ is registered: check the plate",)),
        State("unknown number", "TRK-2026-999999-A", ("on record",)),
    ]
