"""The bundle's reader is strict (app/trust/bundle.py): any member more or less, a wrong type, an
unsorted revocation list, another header or a changed byte is refused with its code, before use."""

from __future__ import annotations

import base64
import json
from typing import Any

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

from app.trust.bundle import BundleRefused, b64url, open_bundle, sign_bundle, unpack_bundle
from app.trust.signer import MemorySigner

SIGNER = MemorySigner(Ed25519PrivateKey.generate(), "file")
KEY = {
    "kid": SIGNER.kid,
    "x": SIGNER.public_jwk()["x"],
    "status": "active",
    "from": 1_790_000_000,
    "until": None,
    "numbers": [2026000001, None],
    "endorsements": [],
}
PAYLOAD: dict[str, Any] = {
    "v": 1,
    "authority": "Tricycle Lateral Stability Certification Authority",
    "issuer": "trikecert.example.ng",
    "seq": 7,
    "made_at": 1_796_320_800,
    "max_age": 259_200,
    "keys": [KEY],
    "revoked": [[2026000003, 20261201, "R"], [2026000009, 20261202, "S"]],
}


def code_of(text: str) -> str:
    with pytest.raises(BundleRefused) as refused:
        open_bundle(text, trusted={SIGNER.kid: KEY["x"]})
    return refused.value.code


def test_a_well_formed_bundle_opens() -> None:
    opened = open_bundle(sign_bundle(PAYLOAD, kid=SIGNER.kid, key=SIGNER), trusted={SIGNER.kid: KEY["x"]})
    assert opened.bundle.revoked == {2026000003: (20261201, "R"), 2026000009: (20261202, "S")}
    assert opened.bundle.keys[0].numbers == (2026000001, None)


@pytest.mark.parametrize(
    "change",
    [
        {"extra": 1},
        {"v": 2},
        {"v": True},
        {"seq": "7"},
        {"seq": -1},
        {"max_age": 0},
        {"keys": []},
        {"keys": [{**KEY, "status": "lost"}]},
        {"keys": [{**KEY, "numbers": [2026000009, 2026000001]}]},
        {"keys": [{**KEY, "x": KEY["x"][:-2]}]},
        {"keys": [{**KEY, "endorsements": [{"rel": "friend", "by": SIGNER.kid, "at": 1, "sig": "AA"}]}]},
        {"keys": [KEY, KEY]},
        {"revoked": [[2026000009, 20261202, "S"], [2026000003, 20261201, "R"]]},
        {"revoked": [[2026000003, 20261201, "X"]]},
        {"revoked": [[2026000003, 2026120, "R"]]},
    ],
)
def test_a_payload_not_of_the_exact_shape_is_unreadable(change: dict[str, Any]) -> None:
    assert code_of(sign_bundle({**PAYLOAD, **change}, kid=SIGNER.kid, key=SIGNER)) == "bundle_unreadable"


def test_another_header_a_changed_byte_or_an_inactive_signer_is_refused() -> None:
    good = sign_bundle(PAYLOAD, kid=SIGNER.kid, key=SIGNER)
    header, payload, signature = good.split(".")
    other = b64url(json.dumps({"alg": "EdDSA", "kid": SIGNER.kid, "typ": "JWT"}).encode())
    assert code_of(f"{other}.{payload}.{signature}") == "bundle_unreadable"
    changed = json.loads(base64.urlsafe_b64decode(payload + "=="))
    changed["seq"] = 8
    assert code_of(f"{header}.{b64url(json.dumps(changed).encode())}.{signature}") == "bundle_bad_signature"
    retired = {**PAYLOAD, "keys": [{**KEY, "status": "retired", "until": 1_796_000_000, "numbers": [1, 2]}]}
    assert code_of(sign_bundle(retired, kid=SIGNER.kid, key=SIGNER)) == "bundle_bad_signature"
    assert code_of(good + "x") == "bundle_unreadable"
    assert code_of("") == "bundle_unreadable"
    assert unpack_bundle(good).kid == SIGNER.kid
