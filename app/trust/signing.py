"""Sign a certificate's QR payload, build the URL the QR code holds, and check what a scan gives back.

New certificates carry a base45 COSE_Sign1 CWT (cwt.py) in a short upper-case URL,
`HTTPS://HOST/V/<payload>`, so the whole QR code is in alphanumeric mode. Certificates issued
before carry a JWS (jws.py) in `<base>/verify/<number>?p=<token>`; both keep verifying, with the
same published keys. Pure: no database.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any
from urllib.parse import quote, unquote, urlsplit

from app.trust.claims import Claims, PayloadRefused, Verified
from app.trust.cwt import sign_cwt, verify_cwt
from app.trust.jws import looks_like_jws, verify_jws
from app.trust.numbers import normalise
from app.trust.signer import SignsBytes

__all__ = [
    "Claims",
    "PayloadRefused",
    "Verified",
    "issuer_claim",
    "legacy_qr_url",
    "qr_url",
    "qr_url_of",
    "sign_payload",
    "split_verify_input",
    "verify_input",
    "verify_payload",
]

SHORT_PATH = "/V/"
# In a URL path these base45 characters must be percent-escaped: space, '%' and '/' (a segment
# separator). '%', '2', '0', '5' and 'F' are in the QR alphanumeric set, so the URL stays in it.
_PATH_SAFE = "$*+-.:"
_SHORT = re.compile(r"/[Vv]/(?P<payload>.+)$")


def sign_payload(claims: Claims, *, kid: str, key: SignsBytes) -> str:
    """The QR payload of new certificates: the base45 COSE_Sign1 CWT of the claims."""
    return sign_cwt(claims, kid=kid, key=key)


def short_base(base_url: str) -> str:
    """The base URL with its scheme and host in capitals (case-insensitive there, alphanumeric in a QR)."""
    url = urlsplit(base_url.rstrip("/"))
    return f"{url.scheme.upper()}://{url.netloc.upper()}{url.path}"


def issuer_claim(base_url: str) -> str:
    """The issuer a CWT signs: the base URL without its scheme, host in lower case ('x.example.ng/path')."""
    url = urlsplit(base_url.rstrip("/"))
    return f"{url.netloc.lower()}{url.path}"


def qr_url(base_url: str, payload: str) -> str:
    """What the QR code encodes: `<BASE>/V/<payload>` for a CWT, `<base>/verify/<number>?p=` for a JWS."""
    if looks_like_jws(payload):
        raise ValueError("a JWS payload has its verify URL with the number; see legacy_qr_url")
    return f"{short_base(base_url)}{SHORT_PATH}{quote(payload, safe=_PATH_SAFE)}"


def legacy_qr_url(base_url: str, number: str, payload: str) -> str:
    """The URL the QR codes of certificates signed with a JWS hold."""
    return f"{base_url.rstrip('/')}/verify/{number}?p={payload}"


def qr_url_of(base_url: str, number: str, payload: str) -> str:
    """The URL a certificate's QR code holds, for either payload format."""
    if looks_like_jws(payload):
        return legacy_qr_url(base_url, number, payload)
    return qr_url(base_url, payload)


def query_values(query: str, name: str) -> list[str]:
    """The values of one query parameter, percent-decoded but with '+' kept: base45 uses it as itself."""
    values = []
    for pair in query.split("&"):
        key, equals, value = pair.partition("=")
        if equals and unquote(key) == name:
            values.append(unquote(value))
    return values


def verify_payload(payload: str, jwks: dict[str, Any]) -> Verified:
    """Check a bare payload of either format against the published keys."""
    payload = payload.strip("\r\n\t")  # not spaces: base45 has them
    if looks_like_jws(payload):
        return verify_jws(payload, jwks)
    return verify_cwt(payload, jwks)


@dataclass(frozen=True)
class VerifyInput:
    """A payload, and the certificate number when it came in a verify URL that names one."""

    token: str
    number: str | None


def split_verify_input(text: str) -> VerifyInput:
    """Accept a bare payload, a QR URL `<BASE>/V/<payload>` or a verify URL `<base>/verify/<number>?p=`."""
    text = text.strip()
    if not text.lower().startswith(("http://", "https://")) and "?p=" not in text:
        return VerifyInput(token=text, number=None)
    url = urlsplit(text)
    short = _SHORT.search(url.path)
    if short is not None and "/verify/" not in url.path:
        return VerifyInput(token=unquote(short.group("payload")), number=None)
    tokens = query_values(url.query, "p")
    if len(tokens) != 1:
        raise PayloadRefused(
            "malformed", "malformed URL: expected /V/<payload> or exactly one p= parameter holding it"
        )
    path = unquote(url.path)
    number = path.rsplit("/verify/", 1)[1] if "/verify/" in path else None
    return VerifyInput(token=tokens[0], number=number or None)


def verify_input(text: str, jwks: dict[str, Any]) -> Verified:
    """Verify a payload or a URL; a URL whose number differs from the signed number is tampered."""
    given = split_verify_input(text)
    verified = verify_payload(given.token, jwks)
    if given.number is not None and normalise(given.number) != normalise(verified.claims.number):
        raise PayloadRefused(
            "tampered",
            f"tampered content: the URL names {given.number!r} but the payload is signed for "
            f"{verified.claims.number}",
        )
    return verified
