"""What signs: one small interface for every place a private key can be held outside the database.

A `Signer` signs bytes with Ed25519 and names its key (kid, public JWK); a `KeyStore` hands out the
signer in force (making a key on first use where it can) and rotates: a new key is put in force and
the one before it is destroyed. A key file (keyfile.py), a PKCS#11 token (pkcs11_token.py) and a
key given in the configuration implement it here; a hardware HSM or a cloud KMS is one more class
with the same three methods. The database never sees a private key: keys.py records public halves.
"""

from __future__ import annotations

import base64
import binascii
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Protocol

from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey
from joserfc.jwk import OKPKey

from app.errors import Conflict, InvalidInput, ServiceError

KID_LENGTH = 16


class SignsBytes(Protocol):
    """Anything that makes an Ed25519 signature of bytes (a Signer, or a `cryptography` private key)."""

    def sign(self, data: bytes) -> bytes:
        """The Ed25519 signature of `data` (64 bytes)."""
        ...


class Signer(Protocol):
    """An Ed25519 private key, wherever it is held: it signs bytes and names its public key."""

    @property
    def kid(self) -> str:
        """The key id (the start of the RFC 7638 thumbprint of the public key)."""
        ...

    @property
    def source(self) -> str:
        """Where the private key is held: "file", "pkcs11" or "configuration"."""
        ...

    def public_jwk(self) -> dict[str, Any]:
        """The public half as a JWK {kty, crv, x}."""
        ...

    def sign(self, data: bytes) -> bytes:
        """The Ed25519 signature of `data` (64 bytes)."""
        ...


class KeyStore(Protocol):
    """Where the signing key lives: the key in force, and rotation that destroys the key it replaces."""

    def describe(self) -> str:
        """Where the key is held, for messages (a path, a token's label)."""
        ...

    def current(self) -> Signer:
        """The key in force, made on first use when the store can make one."""
        ...

    def rotate(self, handover: Handover | None = None) -> Signer:
        """Put a new key in force and destroy the one it replaces; the new key's signer. `handover`
        is called with the old key (None if there was none) and the new one after the new key exists
        and before the old one is destroyed: the two sign their statements about each other then."""
        ...


# Called at a rotation with (old signer or None, new signer) while both keys can still sign.
Handover = Callable[[Signer | None, Signer], None]


class KeyUnavailable(ServiceError):
    """The signing key cannot be read, made or used where the settings say it is held (503: nothing
    is signed until the operator puts it right)."""

    status = 503


def public_jwk_of(public: Ed25519PublicKey) -> dict[str, Any]:
    """The JWK of an Ed25519 public key."""
    raw = public.public_bytes(serialization.Encoding.Raw, serialization.PublicFormat.Raw)
    return {"kty": "OKP", "crv": "Ed25519", "x": base64.urlsafe_b64encode(raw).rstrip(b"=").decode()}


def kid_of_jwk(jwk: dict[str, Any]) -> str:
    """The key id of a public JWK: the start of its RFC 7638 thumbprint."""
    return OKPKey.import_key({name: jwk[name] for name in ("kty", "crv", "x")}).thumbprint()[:KID_LENGTH]


@dataclass(frozen=True)
class MemorySigner:
    """A key held in this process's memory, read from a file or from the configuration."""

    private: Ed25519PrivateKey
    source: str

    @cached_property
    def kid(self) -> str:
        """The key id."""
        return kid_of_jwk(self.public_jwk())

    def public_jwk(self) -> dict[str, Any]:
        """The public half as a JWK."""
        return public_jwk_of(self.private.public_key())

    def sign(self, data: bytes) -> bytes:
        """Ed25519 over `data`."""
        return self.private.sign(data)


def private_pem(key: Ed25519PrivateKey) -> str:
    """The private key as unencrypted PKCS#8 PEM."""
    return key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    ).decode()


def parse_private_key(value: str, *, setting: str = "TRIKECERT_SIGNING_KEY") -> Ed25519PrivateKey:
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
            f"{setting}: give an Ed25519 private key as PEM, base64 of the PEM, "
            "or base64 of the 32-byte seed",
            field="signing_key",
            rule="format",
        ) from error
    if not isinstance(key, Ed25519PrivateKey):
        raise InvalidInput(f"{setting}: the key is not an Ed25519 key", field="signing_key", rule="type")
    return key


@dataclass(frozen=True)
class ConfiguredKey:
    """The key given whole in TRIKECERT_SIGNING_KEY: it cannot be rotated from here."""

    value: str

    def describe(self) -> str:
        """Where the key is held."""
        return "TRIKECERT_SIGNING_KEY"

    def current(self) -> Signer:
        """The configured key."""
        return MemorySigner(parse_private_key(self.value), "configuration")

    def rotate(self, handover: Handover | None = None) -> Signer:
        """Refused: the operator rotates a configured key by changing the setting."""
        raise Conflict(
            "the signing key is given by TRIKECERT_SIGNING_KEY; rotate it by changing that setting",
            field="signing_key",
            rule="configured",
        )
