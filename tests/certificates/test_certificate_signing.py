"""The QR payload issued before the CWT (pure): JWS compact with Ed25519. Such payloads keep verifying
through the same entry point as the new ones, and every kind of forgery is refused with a reason."""

from __future__ import annotations

import base64
import json
from datetime import date
from typing import Any

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from joserfc.jwk import OKPKey

from app.errors import InvalidInput
from app.trust.jws import sign_jws as sign_claims
from app.trust.jws import verify_jws as verify_token
from app.trust.keys import kid_of, okp_key, parse_private_key, private_pem, public_jwk
from app.trust.numbers import CertificateNumber
from app.trust.signing import Claims, PayloadRefused, verify_input

NUMBER = str(CertificateNumber(2026, 123))
CLAIMS = Claims(NUMBER, "BDG 252 QH", date(2026, 11, 23), date(2027, 11, 23), "NC", 1)


def new_key() -> tuple[str, OKPKey]:
    key = okp_key(Ed25519PrivateKey.generate())
    return kid_of(key), key


def jwks(*keys: tuple[str, OKPKey]) -> dict[str, Any]:
    return {"keys": [{**public_jwk(key), "kid": kid} for kid, key in keys]}


def b64(data: bytes) -> str:
    return base64.urlsafe_b64encode(data).rstrip(b"=").decode()


def refusal(token: str, keys: dict[str, Any]) -> str:
    with pytest.raises(PayloadRefused) as refused:
        verify_input(token, keys)
    return refused.value.reason


def test_a_signed_payload_verifies_with_the_published_key_and_gives_back_its_claims() -> None:
    signer = new_key()
    token = sign_claims(CLAIMS, kid=signer[0], key=signer[1])
    header = json.loads(base64.urlsafe_b64decode(token.split(".")[0] + "=="))
    assert header == {"alg": "Ed25519", "kid": signer[0]}
    verified = verify_token(token, jwks(new_key(), signer))
    assert verified.claims == CLAIMS
    assert verified.kid == signer[0]
    assert len(token) < 320  # keeps the QR code small


def test_a_verify_url_is_accepted_and_its_number_must_match_the_signed_one() -> None:
    signer = new_key()
    token = sign_claims(CLAIMS, kid=signer[0], key=signer[1])
    assert verify_input(f"https://x.example/verify/{NUMBER}?p={token}", jwks(signer)).claims == CLAIMS
    assert verify_input(f"https://x.example/verify/{NUMBER.lower()}?p={token}", jwks(signer)).claims == CLAIMS
    other = str(CertificateNumber(2026, 124))
    assert refusal(f"https://x.example/verify/{other}?p={token}", jwks(signer)) == "tampered"
    assert refusal(f"https://x.example/verify/{NUMBER}", jwks(signer)) == "malformed"


@pytest.mark.parametrize(
    ("forge", "reason"),
    [
        (lambda t, k: t.replace(t.split(".")[1], b64(json.dumps({"num": NUMBER}).encode())), "bad_signature"),
        (lambda t, k: ".".join(t.split(".")[:2]) + "." + b64(b"\0" * 64), "bad_signature"),
        (lambda t, k: t.split(".")[0] + "." + t.split(".")[1] + ".", "malformed"),
        (lambda t, k: "not a payload", "malformed"),
        (lambda t, k: b64(b'{"alg":"none","kid":"x"}') + "." + t.split(".", 1)[1], "unsupported_algorithm"),
        (
            lambda t, k: (
                b64(json.dumps({"alg": "Ed25519", "kid": "nobody"}).encode()) + "." + t.split(".", 1)[1]
            ),
            "unknown_key",
        ),
    ],
    ids=["changed claims", "zero signature", "no signature", "garbage", "alg none", "unknown kid"],
)
def test_forgeries_are_refused_with_their_reason(forge: Any, reason: str) -> None:
    signer = new_key()
    token = sign_claims(CLAIMS, kid=signer[0], key=signer[1])
    assert refusal(forge(token, signer), jwks(signer)) == reason


def test_a_payload_signed_by_another_key_under_our_key_id_is_a_bad_signature() -> None:
    ours, theirs = new_key(), new_key()
    token = sign_claims(CLAIMS, kid=ours[0], key=theirs[1])
    assert refusal(token, jwks(ours)) == "bad_signature"


def test_a_key_that_was_never_published_is_unknown() -> None:
    token = sign_claims(CLAIMS, kid="rotated-away", key=new_key()[1])
    assert refusal(token, jwks(new_key())) == "unknown_key"


def test_non_canonical_base64_in_the_last_character_is_refused() -> None:
    """The last character of a 64-byte signature carries 4 unused bits; changing only those is caught."""
    signer = new_key()
    token = sign_claims(CLAIMS, kid=signer[0], key=signer[1])
    last = token[-1]
    alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_"
    twin = alphabet[alphabet.index(last) ^ 1]  # same top bits, different unused bits
    assert refusal(token[:-1] + twin, jwks(signer)) in ("malformed", "bad_signature")


def test_genuinely_signed_but_malformed_claims_are_tampered_content() -> None:
    signer = new_key()
    wrong_letter = "A" if not NUMBER.endswith("A") else "B"
    bad = Claims(NUMBER[:-1] + wrong_letter, "BDG 252 QH", date(2026, 11, 23), date(2027, 11, 23), "NC", 1)
    token = sign_claims(bad, kid=signer[0], key=signer[1])
    assert refusal(token, jwks(signer)) == "tampered"


def test_private_keys_are_read_from_pem_base64_pem_or_a_base64_seed() -> None:
    private = Ed25519PrivateKey.generate()
    pem = private_pem(private)
    kid = kid_of(okp_key(private))
    for given in (
        pem,
        base64.b64encode(pem.encode()).decode(),
        base64.b64encode(private.private_bytes_raw()).decode(),
        pem.replace("\n", "\\n"),
    ):
        assert kid_of(okp_key(parse_private_key(given))) == kid
    with pytest.raises(InvalidInput):
        parse_private_key("not a key")
