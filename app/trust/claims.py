"""What a certificate's QR code vouches for, whichever format signed it, and why a payload is refused.

Pure: no database. Both payload formats (cwt.py, issued now; jws.py, issued before) give back
these claims, so the verify page, the JSON verification and `trikecert verify` check them alike.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import date, datetime
from typing import Any, Literal

Verdict = Literal["C", "NC"]
DocumentKind = Literal["certificate", "refusal"]
Reason = Literal[
    "malformed", "unsupported_algorithm", "unknown_key", "withdrawn_key", "bad_signature", "tampered"
]


class PayloadRefused(Exception):
    """The payload is not a genuine certificate payload; `reason` is a short code, the message says why."""

    def __init__(self, reason: Reason, message: str) -> None:
        super().__init__(message)
        self.reason = reason
        self.message = message


@dataclass(frozen=True)
class Claims:
    """Number, registration, issue and expiry dates (as printed), verdict and maximum occupancy.

    A CWT also signs the exact moments (`issued_at`, `expires_at`), and since 2026-12 the issuer (its
    base URL) and the document's kind; they are not compared, because a payload issued before
    carries only the dates, and the dates are what the paper prints. The kind, when signed, always
    agrees with the verdict (the verifier refuses a payload where it does not).
    """

    number: str
    registration: str
    issued: date
    expires: date
    verdict: Verdict
    max_occupants: int
    issued_at: datetime | None = field(default=None, compare=False)
    expires_at: datetime | None = field(default=None, compare=False)
    issuer: str | None = field(default=None, compare=False)
    kind: DocumentKind | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Verified:
    """A payload whose signature checks out, with the key that signed it and its format."""

    claims: Claims
    kid: str
    format: Literal["cwt", "jws"]


def find_key(jwks: dict[str, Any], kid: str) -> dict[str, Any] | None:
    """The public key with this id in a published key set, or None."""
    for key in jwks.get("keys", []):
        if isinstance(key, dict) and key.get("kid") == kid:
            return key
    return None


def usable_key(jwks: dict[str, Any], kid: str) -> dict[str, Any]:
    """The published key with this id; PayloadRefused when there is none, or it was withdrawn."""
    public = find_key(jwks, kid)
    if public is None:
        raise PayloadRefused("unknown_key", f"unknown key: no published key has the id {kid!r}")
    if public.get("status") == "compromised":
        raise PayloadRefused(
            "withdrawn_key",
            f"withdrawn key: the key {kid} was withdrawn by the issuing authority (it may have been misused)",
        )
    return public


def tampered(error: Exception) -> PayloadRefused:
    """A genuinely signed payload whose claims do not have the expected shape."""
    return PayloadRefused("tampered", f"tampered content: the signed claims are not valid ({error})")
