"""The QR payload issued before the CWT: a JWS compact token (RFC 7515) signed with Ed25519 (RFC 9864).

Header `{"alg": "Ed25519", "kid": ...}`; payload compact JSON claims. No new certificate gets one,
but every one issued stays verifiable, so this module keeps its verifier (and its signer, with
which the tests make such payloads). Pure: no database.
"""

from __future__ import annotations

import base64
import binascii
import json
import re
from datetime import date
from typing import Any

from joserfc import jws
from joserfc.errors import JoseError
from joserfc.jwk import OKPKey

from app.trust.claims import Claims, PayloadRefused, Verdict, Verified, tampered, usable_key
from app.trust.numbers import InvalidNumber, parse_number

ALGORITHM = "Ed25519"
_SHAPE = re.compile(r"^[A-Za-z0-9_=-]*\.[A-Za-z0-9_=-]*\.[A-Za-z0-9_=-]*$")


def looks_like_jws(text: str) -> bool:
    """Three dot-separated base64url parts: the earlier format (a CWT's base45 has no lower case)."""
    return bool(_SHAPE.match(text)) and any(char.islower() for char in text)


def _claims_json(claims: Claims) -> bytes:
    body = {
        "num": claims.number,
        "reg": claims.registration,
        "issued": claims.issued.isoformat(),
        "expires": claims.expires.isoformat(),
        "verdict": claims.verdict,
        "max_occ": claims.max_occupants,
    }
    return json.dumps(body, separators=(",", ":"), ensure_ascii=False).encode()


def _claims_of(data: bytes) -> Claims:
    try:
        body = json.loads(data)
        claims = Claims(
            number=_text(body["num"]),
            registration=_text(body["reg"]),
            issued=date.fromisoformat(_text(body["issued"])),
            expires=date.fromisoformat(_text(body["expires"])),
            verdict=_verdict(body["verdict"]),
            max_occupants=_count(body["max_occ"]),
        )
        parse_number(claims.number)
    except (ValueError, KeyError, TypeError, InvalidNumber) as error:
        raise tampered(error) from error
    return claims


def _text(value: Any) -> str:
    if not isinstance(value, str):
        raise TypeError("expected text")
    return value


def _verdict(value: Any) -> Verdict:
    if value == "C":
        return "C"
    if value == "NC":
        return "NC"
    raise ValueError(f"unknown verdict {value!r}")


def _count(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError("max occupancy must be a whole number")
    return value


def sign_jws(claims: Claims, *, kid: str, key: OKPKey) -> str:
    """The JWS compact token of the claims, as certificates were signed before the CWT."""
    return jws.serialize_compact(
        {"alg": ALGORITHM, "kid": kid}, _claims_json(claims), key, algorithms=[ALGORITHM]
    )


def _b64decode(segment: str, part: str) -> bytes:
    """Strict base64url: refuse padding, stray characters and non-canonical trailing bits."""
    try:
        raw = base64.urlsafe_b64decode(segment + "=" * (-len(segment) % 4))
    except (binascii.Error, ValueError) as error:
        raise PayloadRefused("malformed", f"malformed payload: the {part} is not base64url") from error
    if base64.urlsafe_b64encode(raw).rstrip(b"=").decode() != segment:
        raise PayloadRefused("malformed", f"malformed payload: the {part} is not canonical base64url")
    return raw


def verify_jws(token: str, jwks: dict[str, Any]) -> Verified:
    """Check a JWS compact token against the published keys; PayloadRefused says why it is not genuine."""
    token = token.strip()
    parts = token.split(".")
    if len(parts) != 3 or not all(parts):
        raise PayloadRefused(
            "malformed", "malformed payload: expected three dot-separated parts (JWS compact)"
        )
    header_raw = _b64decode(parts[0], "header")
    _b64decode(parts[1], "content")
    _b64decode(parts[2], "signature")
    try:
        header = json.loads(header_raw)
    except ValueError as error:
        raise PayloadRefused("malformed", "malformed payload: the header is not JSON") from error
    if not isinstance(header, dict) or set(header) != {"alg", "kid"}:
        raise PayloadRefused("malformed", "malformed payload: the header must hold exactly alg and kid")
    if header["alg"] != ALGORITHM:
        raise PayloadRefused(
            "unsupported_algorithm", f"unsupported algorithm {header['alg']!r}; expected Ed25519"
        )
    kid = header["kid"]
    if not isinstance(kid, str):
        raise PayloadRefused("unknown_key", f"unknown key: no published key has the id {kid!r}")
    public = usable_key(jwks, kid)
    try:
        key = OKPKey.import_key({k: public[k] for k in ("kty", "crv", "x")})
        verified = jws.deserialize_compact(token, key, algorithms=[ALGORITHM])
    except (JoseError, KeyError, ValueError, TypeError) as error:
        raise PayloadRefused(
            "bad_signature",
            "bad signature: the content or the signature was altered, or it was not signed by us",
        ) from error
    return Verified(claims=_claims_of(verified.payload), kid=kid, format="jws")
