"""The signing key on a PKCS#11 token (an HSM; SoftHSM2 for tests and small sites), via python-pkcs11.

The key pair is made on the token (CKM_EC_EDWARDS_KEY_PAIR_GEN, Ed25519), marked sensitive and not
extractable, and found by its label; signing is CKM_EDDSA on the token. Rotation makes a new pair
under a temporary label, destroys the old pair on the token, then gives the new pair the label; a
rotation cut short is finished the next time the key is looked up. Install the optional extra
`trikecert[pkcs11]` and set TRIKECERT_PKCS11_MODULE (and the token's label and PIN) to use it.
"""

from __future__ import annotations

import base64
import secrets
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cached_property, lru_cache
from pathlib import Path
from typing import Any

from app.config import Settings
from app.trust.signer import Handover, KeyUnavailable, kid_of_jwk

ED25519_OID = "1.3.101.112"
PENDING = ".new"


def _unavailable(message: str) -> KeyUnavailable:
    return KeyUnavailable(f"PKCS#11 token: {message}", field="pkcs11_module", rule="unavailable")


class _Token:
    """One logged-in read-write session on the token, shared by the threads of this process."""

    def __init__(self, module: Path, token_label: str, pin: str) -> None:
        try:
            import pkcs11
        except ImportError as error:
            raise _unavailable(
                "python-pkcs11 is not installed; install trikecert[pkcs11] to use TRIKECERT_PKCS11_MODULE"
            ) from error
        self.pkcs11: Any = pkcs11
        try:
            token = pkcs11.lib(str(module)).get_token(token_label=token_label)
            self.session: Any = token.open(rw=True, user_pin=pin)
        except (pkcs11.PKCS11Error, RuntimeError, OSError) as error:
            raise _unavailable(f"cannot open token {token_label!r} with {module}: {error!r}") from error
        self.lock = threading.Lock()

    @contextmanager
    def failures(self, doing: str) -> Iterator[None]:
        """A token's refusal (removed, logged out, out of space) as a 503 naming what failed."""
        try:
            yield
        except self.pkcs11.PKCS11Error as error:
            raise _unavailable(f"cannot {doing}: {error!r}") from error

    def pairs(self, label: str) -> list[tuple[Any, Any]]:
        """The key pairs with this label, as (private, public), by kid."""
        classes = self.pkcs11.ObjectClass
        attribute = self.pkcs11.Attribute
        found: dict[bytes, list[Any]] = {}
        for object_class in (classes.PRIVATE_KEY, classes.PUBLIC_KEY):
            for item in self.session.get_objects({attribute.CLASS: object_class, attribute.LABEL: label}):
                found.setdefault(bytes(item[attribute.ID]), [None, None])[
                    0 if object_class == classes.PRIVATE_KEY else 1
                ] = item
        return [(private, public) for private, public in found.values() if private and public]

    def generate(self, label: str) -> None:
        """A new Ed25519 pair on the token, sensitive and not extractable."""
        from pkcs11.util.ec import encode_named_curve_parameters

        attribute, mechanism = self.pkcs11.Attribute, self.pkcs11.Mechanism
        parameters = self.session.create_domain_parameters(
            self.pkcs11.KeyType.EC_EDWARDS,
            {attribute.EC_PARAMS: encode_named_curve_parameters(ED25519_OID)},
            local=True,
        )
        identifier = secrets.token_bytes(16)
        parameters.generate_keypair(
            mechanism=mechanism.EC_EDWARDS_KEY_PAIR_GEN,
            store=True,
            label=label,
            id=identifier,
            private_template={attribute.SENSITIVE: True, attribute.EXTRACTABLE: False},
        )

    def relabel(self, pair: tuple[Any, Any], label: str) -> None:
        """Give both halves of a pair a new label."""
        for item in pair:
            item[self.pkcs11.Attribute.LABEL] = label

    def destroy(self, pair: tuple[Any, Any]) -> None:
        """Destroy both halves of a pair on the token."""
        for item in pair:
            item.destroy()


@lru_cache
def _token(module: Path, token_label: str, pin: str) -> _Token:
    return _Token(module, token_label, pin)


@dataclass(frozen=True)
class TokenSigner:
    """A private key on the token: it never leaves it."""

    token: _Token
    private: Any
    jwk: dict[str, Any]
    source: str = "pkcs11"

    @cached_property
    def kid(self) -> str:
        """The key id."""
        return kid_of_jwk(self.jwk)

    def public_jwk(self) -> dict[str, Any]:
        """The public half as a JWK."""
        return dict(self.jwk)

    def sign(self, data: bytes) -> bytes:
        """CKM_EDDSA on the token."""
        with self.token.lock, self.token.failures("sign"):
            signature: bytes = self.private.sign(data, mechanism=self.token.pkcs11.Mechanism.EDDSA)
        return signature


def _jwk(token: _Token, public: Any) -> dict[str, Any]:
    point = bytes(public[token.pkcs11.Attribute.EC_POINT])
    if len(point) == 34 and point[:2] == b"\x04\x20":  # DER OCTET STRING around the 32 bytes
        point = point[2:]
    x = base64.urlsafe_b64encode(point).rstrip(b"=").decode()
    return {"kty": "OKP", "crv": "Ed25519", "x": x}


@dataclass(frozen=True)
class TokenStore:
    """The key store of a PKCS#11 token: the pair with the configured label."""

    token: _Token
    token_label: str
    key_label: str

    def describe(self) -> str:
        """The token and the key's label."""
        return f"PKCS#11 token {self.token_label!r} (key {self.key_label!r})"

    def _signer(self, pair: tuple[Any, Any]) -> TokenSigner:
        return TokenSigner(self.token, pair[0], _jwk(self.token, pair[1]))

    def _in_force(self) -> TokenSigner | None:
        pairs = [(self._signer(pair), pair) for pair in self.token.pairs(self.key_label)]
        if not pairs:
            return None
        pairs.sort(key=lambda found: found[0].kid)
        for _signer, extra in pairs[1:]:  # two processes made a first key at once: one is kept
            self.token.destroy(extra)
        return pairs[0][0]

    def current(self) -> TokenSigner:
        """The pair with the key label; a rotation cut short is finished, a first pair made."""
        with self.token.lock, self.token.failures("find or make the signing key"):
            signer = self._in_force()
            if signer is None:
                pending = self.token.pairs(self.key_label + PENDING)
                if pending:
                    self.token.relabel(pending[0], self.key_label)
                else:
                    self.token.generate(self.key_label)
                signer = self._in_force()
        assert signer is not None
        return signer

    def rotate(self, handover: Handover | None = None) -> TokenSigner:
        """A new pair under a temporary label, `handover` while both can sign (outside the lock: each
        signature takes it), the old pair destroyed, the new one labelled."""
        with self.token.lock, self.token.failures("rotate the signing key"):
            old = self._in_force()
            self.token.generate(self.key_label + PENDING)
            new = self._signer(self.token.pairs(self.key_label + PENDING)[0])
        if handover is not None:
            try:
                handover(old, new)
            except BaseException:
                with self.token.lock, self.token.failures("drop the new signing key"):
                    for pair in self.token.pairs(self.key_label + PENDING):
                        self.token.destroy(pair)
                raise
        with self.token.lock:
            self._finish_rotation()
        return self.current()

    def _finish_rotation(self) -> None:
        with self.token.failures("rotate the signing key"):
            for pair in self.token.pairs(self.key_label):
                self.token.destroy(pair)
            for pair in self.token.pairs(self.key_label + PENDING):
                self.token.relabel(pair, self.key_label)


def token_store(settings: Settings) -> TokenStore:
    """The token the settings name (TRIKECERT_PKCS11_MODULE, _TOKEN_LABEL, _PIN, _KEY_LABEL)."""
    assert settings.pkcs11_module is not None
    if settings.pkcs11_pin is None:
        raise _unavailable("set TRIKECERT_PKCS11_PIN to the token's user PIN")
    token = _token(
        settings.pkcs11_module, settings.pkcs11_token_label, settings.pkcs11_pin.get_secret_value()
    )
    return TokenStore(token, settings.pkcs11_token_label, settings.pkcs11_key_label)
