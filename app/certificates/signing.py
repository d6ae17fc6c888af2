"""The signed QR payload: a JWS compact token (RFC 7515) signed with Ed25519 (alg "Ed25519", RFC 9864).

Header `{"alg": "Ed25519", "kid": ...}`; payload the JSON claims below. Verification needs only the
published public keys (a JWKS), so anyone can check a certificate offline. Pure: no database.
"""

from __future__ import annotations

import base64
import binascii
import json
from dataclasses import dataclass
from datetime import date
from typing import Any, Literal
from urllib.parse import parse_qs, unquote, urlsplit

from joserfc import jws
from joserfc.errors import JoseError
from joserfc.jwk import OKPKey

from app.certificates.numbers import InvalidNumber, normalise, parse_number

ALGORITHM = "Ed25519"
Verdict = Literal["C", "NC"]
Reason = Literal["malformed", "unsupported_algorithm", "unknown_key", "bad_signature", "tampered"]


class PayloadRefused(Exception):
    """The payload is not a genuine certificate payload; `reason` is a short code, the message says why."""

    def __init__(self, reason: Reason, message: str) -> None:
        super().__init__(message)
        self.reason = reason
        self.message = message


@dataclass(frozen=True)
class Claims:
    """What the QR code vouches for: number, registration, dates, verdict and maximum occupancy."""

    number: str
    registration: str
    issued: date
    expires: date
    verdict: Verdict
    max_occupants: int

    def to_json(self) -> bytes:
        """Compact JSON with short, fixed keys (the QR code stays small)."""
        body = {
            "num": self.number,
            "reg": self.registration,
            "issued": self.issued.isoformat(),
            "expires": self.expires.isoformat(),
            "verdict": self.verdict,
            "max_occ": self.max_occupants,
        }
        return json.dumps(body, separators=(",", ":"), ensure_ascii=False).encode()

    @classmethod
    def from_json(cls, data: bytes) -> Claims:
        """Parse signed claims, refusing any that do not have the expected shape."""
        try:
            body = json.loads(data)
            claims = cls(
                number=_text(body["num"]),
                registration=_text(body["reg"]),
                issued=date.fromisoformat(_text(body["issued"])),
                expires=date.fromisoformat(_text(body["expires"])),
                verdict=_verdict(body["verdict"]),
                max_occupants=_count(body["max_occ"]),
            )
            parse_number(claims.number)
        except (ValueError, KeyError, TypeError, InvalidNumber) as error:
            raise PayloadRefused(
                "tampered", f"tampered content: the signed claims are not valid ({error})"
            ) from error
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


def sign_claims(claims: Claims, *, kid: str, key: OKPKey) -> str:
    """The JWS compact token of the claims, signed with the private key `key` known as `kid`."""
    return jws.serialize_compact(
        {"alg": ALGORITHM, "kid": kid}, claims.to_json(), key, algorithms=[ALGORITHM]
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


@dataclass(frozen=True)
class Verified:
    """A payload whose signature checks out, with the key that signed it."""

    claims: Claims
    kid: str


def find_key(jwks: dict[str, Any], kid: str) -> dict[str, Any] | None:
    """The public key with this id in a published key set, or None."""
    for key in jwks.get("keys", []):
        if isinstance(key, dict) and key.get("kid") == kid:
            return key
    return None


def verify_token(token: str, jwks: dict[str, Any]) -> Verified:
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
    public = find_key(jwks, kid) if isinstance(kid, str) else None
    if public is None:
        raise PayloadRefused("unknown_key", f"unknown key: no published key has the id {kid!r}")
    try:
        key = OKPKey.import_key({k: public[k] for k in ("kty", "crv", "x")})
        verified = jws.deserialize_compact(token, key, algorithms=[ALGORITHM])
    except JoseError as error:
        raise PayloadRefused(
            "bad_signature",
            "bad signature: the content or the signature was altered, or it was not signed by us",
        ) from error
    return Verified(claims=Claims.from_json(verified.payload), kid=kid)


@dataclass(frozen=True)
class VerifyInput:
    """A token, and the certificate number when it came as a verify URL."""

    token: str
    number: str | None


def split_verify_input(text: str) -> VerifyInput:
    """Accept a bare token or a verify URL `<base>/verify/<number>?p=<token>`."""
    text = text.strip()
    if "/verify/" not in text and "?p=" not in text:
        return VerifyInput(token=text, number=None)
    url = urlsplit(text)
    tokens = parse_qs(url.query).get("p", [])
    if len(tokens) != 1:
        raise PayloadRefused(
            "malformed", "malformed URL: expected exactly one p= parameter holding the payload"
        )
    path = unquote(url.path)
    number = path.rsplit("/verify/", 1)[1] if "/verify/" in path else None
    return VerifyInput(token=tokens[0], number=number or None)


def verify_input(text: str, jwks: dict[str, Any]) -> Verified:
    """Verify a token or a verify URL; a URL whose number differs from the signed number is tampered."""
    given = split_verify_input(text)
    verified = verify_token(given.token, jwks)
    if given.number is not None and normalise(given.number) != normalise(verified.claims.number):
        raise PayloadRefused(
            "tampered",
            f"tampered content: the URL names {given.number!r} but the payload is signed for "
            f"{verified.claims.number}",
        )
    return verified
