"""Signing keys: held outside the database (a key file, a PKCS#11 token, or the configuration),
rotated, published as a JWKS.

The private key is never stored in the database: the store the settings name (signer.py) holds it,
and the `signing_key` table keeps each key's public half and metadata (kid, source, the period it
signed in), so the published key set verifies every certificate ever issued. The store is the
truth about which key signs: a key found there that the table does not know yet is recorded and
every other key retired; a key the table has retired never signs again. Each published key also
carries its COSE_Key form (`cose_key`), for the CWT payloads of the QR codes.
"""

from __future__ import annotations

import base64
from dataclasses import dataclass, field
from typing import Any

import cbor2
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from joserfc.jwk import OKPKey
from sqlalchemy import func, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from app.config import Settings
from app.db import utcnow
from app.trust.cwt import EDDSA, kid_bytes
from app.trust.jws import ALGORITHM
from app.trust.keyfile import KeyFile, default_key_path
from app.trust.models import SigningKey
from app.trust.signer import (
    KID_LENGTH,
    ConfiguredKey,
    KeyStore,
    KeyUnavailable,
    Signer,
    parse_private_key,
    private_pem,
)

__all__ = [
    "KID_LENGTH",
    "Signer",
    "current_signer",
    "key_store",
    "kid_of",
    "okp_key",
    "parse_private_key",
    "private_pem",
    "public_jwk",
    "published_keys",
    "rotate_signing_key",
]


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


def key_store(settings: Settings) -> KeyStore:
    """Where the settings hold the signing key: TRIKECERT_SIGNING_KEY, else a PKCS#11 token when
    TRIKECERT_PKCS11_MODULE is set, else the key file."""
    if settings.signing_key is not None:
        return ConfiguredKey(settings.signing_key.get_secret_value())
    if settings.pkcs11_module is not None:
        from app.trust.pkcs11_token import token_store

        return token_store(settings)
    return KeyFile(default_key_path(settings))


def _retire_others(session: Session, kid: str) -> None:
    now = utcnow()
    for row in session.scalars(select(SigningKey).where(SigningKey.active.is_(True), SigningKey.kid != kid)):
        row.active = False
        row.retired_at = now


def _record(session: Session, signer: Signer) -> None:
    """Record the signer's public key as the active one and retire every other (flushed)."""
    _retire_others(session, signer.kid)
    row = SigningKey(kid=signer.kid, public_jwk=signer.public_jwk(), source=signer.source, active=True)
    try:
        with session.begin_nested():
            session.add(row)
    except IntegrityError:
        pass  # another process recorded it at the same moment


def current_signer(session: Session, settings: Settings) -> Signer:
    """The key that signs now, from the store the settings name; recorded (public half) if new."""
    store = key_store(settings)
    signer = store.current()
    row = session.scalar(select(SigningKey).where(SigningKey.kid == signer.kid))
    if row is None:
        _record(session, signer)
    elif not row.active:
        raise KeyUnavailable(
            f"the signing key held in {store.describe()} ({signer.kid}) was retired on "
            f"{row.retired_at:%Y-%m-%d} and never signs again; rotate to a new key "
            "(`trikecert rotate-signing-key`)",
            field="signing_key",
            rule="retired",
        )
    return signer


def rotate_signing_key(session: Session, settings: Settings) -> SigningKey:
    """Put a new key in force in the store (destroying the old private key), retire every other key in
    the table and record the new one; old public keys stay published. Commits."""
    signer = key_store(settings).rotate()
    _record(session, signer)
    session.commit()
    row = session.scalar(select(SigningKey).where(SigningKey.kid == signer.kid))
    assert row is not None
    return row


@dataclass(frozen=True)
class TrustedKeys:
    """The key rows trusted online, oldest first; the endorsements about each (by subject kid); the
    kids withdrawn for compromise."""

    rows: list[SigningKey]
    endorsements: dict[str, list[Any]] = field(default_factory=dict)
    withdrawn: set[str] = field(default_factory=set)


def trusted_key_rows(session: Session) -> TrustedKeys:
    """The signing keys this service vouches for (every row, until endorsements are recorded)."""
    return TrustedKeys(list(session.scalars(select(SigningKey).order_by(SigningKey.id))))


def key_event_count(session: Session) -> int:
    """Key events so far: keys recorded, keys retired (each only grows)."""
    recorded = session.scalar(select(func.count()).select_from(SigningKey)) or 0
    retired = session.scalar(select(func.count(SigningKey.retired_at))) or 0
    return int(recorded) + int(retired)


COSE_OKP, COSE_ED25519 = 1, 6  # COSE key type OKP and curve Ed25519 (RFC 9053)


def cose_key(jwk: dict[str, Any], kid: str) -> str:
    """A public key as a COSE_Key {kty: OKP, kid, alg: EdDSA, crv: Ed25519, x}: CBOR in base64url."""
    x = base64.urlsafe_b64decode(jwk["x"] + "=" * (-len(jwk["x"]) % 4))
    key = {1: COSE_OKP, 2: kid_bytes(kid), 3: EDDSA, -1: COSE_ED25519, -2: x}
    return base64.urlsafe_b64encode(cbor2.dumps(key)).rstrip(b"=").decode()


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
