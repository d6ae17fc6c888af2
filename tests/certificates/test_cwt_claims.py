"""The CWT's claims (pure): new payloads sign the issuer and the document's kind; payloads signed
before (without either) keep verifying; a payload of neither layout, or whose kind disagrees with
its verdict, is refused as tampered."""

from __future__ import annotations

from datetime import UTC, date, datetime
from typing import Any

import base45  # type: ignore[import-untyped]
import cbor2
import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

from app.trust.cwt import kid_bytes, sign_cwt
from app.trust.keys import kid_of, okp_key, public_jwk
from app.trust.numbers import CertificateNumber
from app.trust.signing import Claims, PayloadRefused, issuer_claim, verify_payload

NUMBER = CertificateNumber(2026, 123)
ISSUED, EXPIRES = datetime(2026, 11, 23, 9, tzinfo=UTC), datetime(2027, 11, 23, 9, tzinfo=UTC)
CLAIMS = Claims(
    str(NUMBER),
    "BDG 252 QH",
    date(2026, 11, 23),
    date(2027, 11, 23),
    "NC",
    1,
    issued_at=ISSUED,
    expires_at=EXPIRES,
    issuer="trikecert.example.ng",
)


@pytest.fixture
def signer() -> tuple[str, Ed25519PrivateKey, dict[str, Any]]:
    private = Ed25519PrivateKey.generate()
    key = okp_key(private)
    kid = kid_of(key)
    return kid, private, {"keys": [{**public_jwk(key), "kid": kid}]}


def signed(claims: dict[Any, Any], kid: str, private: Ed25519PrivateKey) -> str:
    """A COSE_Sign1 of any claims, signed as the service signs (to make the earlier layout and forgeries)."""
    protected = cbor2.dumps({1: -8, 4: kid_bytes(kid)})
    payload = cbor2.dumps(claims)
    signature = private.sign(cbor2.dumps(["Signature1", protected, b"", payload]))
    text: bytes = base45.b45encode(cbor2.dumps(cbor2.CBORTag(18, [protected, {}, payload, signature])))
    return text.decode()


def ours(compliant: bool = False, kind: int | None = None) -> dict[int, Any]:
    """The trikecert claim; with a kind, as new payloads have it (key 5)."""
    claim: dict[int, Any] = {1: int(NUMBER.digits), 2: "BDG 252 QH", 3: compliant, 4: 1}
    return claim if kind is None else {**claim, 5: kind}


def test_the_issuer_is_the_base_url_without_its_scheme() -> None:
    assert issuer_claim("https://TriKeCert.Example.NG/") == "trikecert.example.ng"
    assert issuer_claim("https://gov.example.ng/TRIKECERT") == "gov.example.ng/TRIKECERT"
    assert issuer_claim("http://127.0.0.1:8000") == "127.0.0.1:8000"


def test_a_new_payload_signs_the_issuer_and_the_kind(
    signer: tuple[str, Ed25519PrivateKey, dict[str, Any]],
) -> None:
    kid, private, keys = signer
    token = sign_cwt(CLAIMS, kid=kid, key=private)
    body = cbor2.loads(cbor2.loads(base45.b45decode(token)).value[2])
    assert body[1] == "trikecert.example.ng"
    assert body[-65537][5] == 2  # a refusal; 1 is a certificate
    verified = verify_payload(token, keys)
    assert verified.claims == CLAIMS
    assert (verified.claims.issuer, verified.claims.kind) == ("trikecert.example.ng", "refusal")
    with pytest.raises(ValueError, match="issuer"):
        sign_cwt(Claims(**{**CLAIMS.__dict__, "issuer": None}), kid=kid, key=private)


def test_a_payload_signed_before_the_issuer_and_kind_claims_still_verifies(
    signer: tuple[str, Ed25519PrivateKey, dict[str, Any]],
) -> None:
    kid, private, keys = signer
    earlier = signed({4: int(EXPIRES.timestamp()), 6: int(ISSUED.timestamp()), -65537: ours()}, kid, private)
    verified = verify_payload(earlier, keys)
    assert verified.claims == CLAIMS
    assert (verified.claims.issuer, verified.claims.kind) == (None, None)


@pytest.mark.parametrize(
    "claims",
    [
        # the issuer without the kind, and the kind without the issuer: neither layout
        {1: "x.example", 4: 1827478800, 6: 1795942800, -65537: ours()},
        {4: 1827478800, 6: 1795942800, -65537: ours(kind=2)},
        # a kind that contradicts the verdict
        {1: "x.example", 4: 1827478800, 6: 1795942800, -65537: ours(kind=1)},
        {1: "x.example", 4: 1827478800, 6: 1795942800, -65537: ours(True, kind=2)},
        # an issuer that is not text, a kind that is not a number
        {1: 7, 4: 1827478800, 6: 1795942800, -65537: ours(kind=2)},
        {1: "x.example", 4: 1827478800, 6: 1795942800, -65537: {**ours(), 5: "refusal"}},
    ],
    ids=[
        "issuer only",
        "kind only",
        "refusal called certificate",
        "certificate called refusal",
        "issuer number",
        "kind text",
    ],
)
def test_a_payload_of_neither_layout_or_with_a_contradicting_kind_is_tampered(
    signer: tuple[str, Ed25519PrivateKey, dict[str, Any]], claims: dict[Any, Any]
) -> None:
    kid, private, keys = signer
    with pytest.raises(PayloadRefused) as refused:
        verify_payload(signed(claims, kid, private), keys)
    assert refused.value.reason == "tampered"
