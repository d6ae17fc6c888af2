"""Test-side makers of what the /check page reads: signed QR payloads and trust bundles (JWS) of keys
held in memory, so that each case (a stale list, a rollback, an unknown key) can be made exactly."""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from cryptography.hazmat.primitives.serialization import Encoding, PublicFormat

from app.trust.cwt import sign_cwt
from app.trust.numbers import CertificateNumber
from app.trust.signer import MemorySigner
from app.trust.signing import Claims

ISSUER = "trikecert.example.ng"
AUTHORITY = "Lagos State Vehicle Inspection Service"


def b64(raw: bytes) -> str:
    """Unpadded base64url."""
    return base64.urlsafe_b64encode(raw).rstrip(b"=").decode()


@dataclass
class Key:
    """A signing key with its bundle entry's facts."""

    status: str = "active"
    since: int = 1_700_000_000
    until: int | None = None
    numbers: list[int | None] | None = field(default_factory=lambda: [2026000001, None])
    signer: MemorySigner = field(
        default_factory=lambda: MemorySigner(private=Ed25519PrivateKey.generate(), source="test")
    )

    @property
    def kid(self) -> str:
        """The key id."""
        return self.signer.kid

    def entry(self) -> dict[str, Any]:
        """The key as the bundle lists it."""
        raw = self.signer.private.public_key().public_bytes(Encoding.Raw, PublicFormat.Raw)
        return {
            "kid": self.kid,
            "x": b64(raw),
            "status": self.status,
            "from": self.since,
            "until": self.until,
            "numbers": self.numbers,
            "endorsements": [],
        }


def payload(
    key: Key,
    *,
    digits: int = 2026000123,
    registration: str = "KTU-417-XA",
    compliant: bool = True,
    occupants: int = 2,
    iat: int = 1_796_000_000,
    exp: int = 1_827_536_000,
    issuer: str = ISSUER,
) -> str:
    """The base45 QR payload of these claims, signed by the key."""
    number = CertificateNumber(digits // 10**6, digits % 10**6)
    claims = Claims(
        number=str(number),
        registration=registration,
        issued=datetime.fromtimestamp(iat, UTC).date(),
        expires=datetime.fromtimestamp(exp, UTC).date(),
        verdict="C" if compliant else "NC",
        max_occupants=occupants,
        issued_at=datetime.fromtimestamp(iat, UTC),
        expires_at=datetime.fromtimestamp(exp, UTC),
        issuer=issuer,
    )
    return sign_cwt(claims, kid=key.kid, key=key.signer)


def bundle(
    signer: Key,
    keys: list[Key],
    *,
    seq: int = 10,
    made_at: int = 1_796_100_000,
    max_age: int = 7 * 86400,
    revoked: list[list[Any]] | None = None,
    issuer: str = ISSUER,
    authority: str = AUTHORITY,
) -> str:
    """The trust bundle's JWS (BUNDLE-SPEC.md), signed by `signer`."""
    header = {"alg": "EdDSA", "kid": signer.kid, "typ": "trikecert-trust+jws"}
    body = {
        "v": 1,
        "authority": authority,
        "issuer": issuer,
        "seq": seq,
        "made_at": made_at,
        "max_age": max_age,
        "keys": [key.entry() for key in keys],
        "revoked": revoked or [],
    }
    signing_input = f"{b64(json.dumps(header).encode())}.{b64(json.dumps(body).encode())}"
    return f"{signing_input}.{b64(signer.signer.sign(signing_input.encode()))}"
