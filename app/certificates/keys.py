"""Signing keys: created on first use (or given by TRIKECERT_SIGNING_KEY), rotated, published as a JWKS.

Every key ever used stays in the `signing_key` table (the private half only when the database
made it), so the published key set verifies every certificate ever issued. Each published key
also carries its COSE_Key form (`cose_key`), for the CWT payloads of the QR codes.
"""

from __future__ import annotations

import base64
import binascii
from dataclasses import dataclass
from typing import Any

import cbor2
from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from joserfc.jwk import OKPKey
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.certificates.cwt import EDDSA, kid_bytes
from app.certificates.jws import ALGORITHM
from app.certificates.models import SigningKey
from app.config import Settings
from app.db import utcnow
from app.errors import Conflict, InvalidInput

KID_LENGTH = 16


@dataclass(frozen=True)
class Signer:
    """The private key that signs new payloads, and its id."""

    kid: str
    key: OKPKey

    @property
    def ed25519(self) -> Ed25519PrivateKey:
        """The private key as `cryptography` holds it (the CWT signer takes it)."""
        private = self.key.private_key
        assert isinstance(private, Ed25519PrivateKey)
        return private


def parse_private_key(value: str) -> Ed25519PrivateKey:
    """An Ed25519 private key from PEM text, base64 of PEM, or base64 of the 32-byte seed."""
    text = value.strip().replace("\\n", "\n")
    try:
        if "-----BEGIN" not in text:
            raw = base64.b64decode(text, validate=True)
            if len(raw) == 32:
                return Ed25519PrivateKey.from_private_bytes(raw)
            text = raw.decode()
        key = serialization.load_pem_private_key(text.encode(), password=None)
    except (ValueError, TypeError, binascii.Error, UnicodeDecodeError) as error:
        raise InvalidInput(
            "TRIKECERT_SIGNING_KEY: give an Ed25519 private key as PEM, base64 of the PEM, "
            "or base64 of the 32-byte seed",
            field="signing_key",
            rule="format",
        ) from error
    if not isinstance(key, Ed25519PrivateKey):
        raise InvalidInput(
            "TRIKECERT_SIGNING_KEY: the key is not an Ed25519 key", field="signing_key", rule="type"
        )
    return key


def private_pem(key: Ed25519PrivateKey) -> str:
    """The private key as unencrypted PKCS#8 PEM."""
    return key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    ).decode()


def okp_key(key: Ed25519PrivateKey) -> OKPKey:
    """The joserfc key object of a private key."""
    return OKPKey.import_key(private_pem(key))


def kid_of(key: OKPKey) -> str:
    """The key id: the start of the RFC 7638 thumbprint of the public key."""
    return key.thumbprint()[:KID_LENGTH]


def public_jwk(key: OKPKey) -> dict[str, Any]:
    """The public half as a JWK."""
    public = key.as_dict(private=False)
    return {"kty": public["kty"], "crv": public["crv"], "x": public["x"]}


COSE_OKP, COSE_ED25519 = 1, 6  # COSE key type OKP and curve Ed25519 (RFC 9053)


def cose_key(jwk: dict[str, Any], kid: str) -> str:
    """A public key as a COSE_Key {kty: OKP, kid, alg: EdDSA, crv: Ed25519, x}: CBOR in base64url."""
    x = base64.urlsafe_b64decode(jwk["x"] + "=" * (-len(jwk["x"]) % 4))
    key = {1: COSE_OKP, 2: kid_bytes(kid), 3: EDDSA, -1: COSE_ED25519, -2: x}
    return base64.urlsafe_b64encode(cbor2.dumps(key)).rstrip(b"=").decode()


def _record(session: Session, key: OKPKey, *, pem: str | None, source: str) -> SigningKey:
    row = SigningKey(kid=kid_of(key), public_jwk=public_jwk(key), private_pem=pem, source=source, active=True)
    session.add(row)
    session.flush()
    return row


def new_database_key(session: Session) -> SigningKey:
    """Create a fresh key, kept in the database, and make it the active one (flushed, not committed)."""
    private = Ed25519PrivateKey.generate()
    return _record(session, okp_key(private), pem=private_pem(private), source="database")


def current_signer(session: Session, settings: Settings) -> Signer:
    """The key that signs now: the configured one, else the newest active database key (made on first use)."""
    if settings.signing_key is not None:
        key = okp_key(parse_private_key(settings.signing_key.get_secret_value()))
        kid = kid_of(key)
        if session.scalar(select(SigningKey.id).where(SigningKey.kid == kid)) is None:
            _record(session, key, pem=None, source="configuration")
        return Signer(kid=kid, key=key)
    row = session.scalar(
        select(SigningKey)
        .where(SigningKey.active.is_(True), SigningKey.private_pem.is_not(None))
        .order_by(SigningKey.id.desc())
        .limit(1)
    )
    if row is None:
        row = new_database_key(session)
    assert row.private_pem is not None
    return Signer(kid=row.kid, key=OKPKey.import_key(row.private_pem))


def rotate_signing_key(session: Session, settings: Settings) -> SigningKey:
    """Retire the active database keys and make a new one; old keys stay published. Commits."""
    if settings.signing_key is not None:
        raise Conflict(
            "the signing key is given by TRIKECERT_SIGNING_KEY; rotate it by changing that setting",
            field="signing_key",
            rule="configured",
        )
    now = utcnow()
    for row in session.scalars(select(SigningKey).where(SigningKey.active.is_(True))):
        row.active = False
        row.retired_at = now
    row = new_database_key(session)
    session.commit()
    return row


def published_keys(session: Session, settings: Settings) -> dict[str, Any]:
    """Every public key ever used, newest first, as a JWKS with the issuer's name and each COSE_Key."""
    rows = session.scalars(select(SigningKey).order_by(SigningKey.id.desc())).all()
    return {
        "issuer": settings.issuing_authority,
        "keys": [
            {
                **row.public_jwk,
                "kid": row.kid,
                "alg": ALGORITHM,
                "use": "sig",
                "active": row.active,
                "created_at": row.created_at.isoformat(),
                "cose_key": cose_key(row.public_jwk, row.kid),
            }
            for row in rows
        ],
    }
