"""The key that makes a contact's digest unguessable.

A phone number's plain SHA-256 is found again by hashing every number there is (Nigeria's mobile
numbers are about 10^9), so anyone who reads the database would learn who subscribed, after the
contact itself was erased. Keyed (HMAC-SHA256), the digests still tell two requests from the same
contact apart for the limits, and reveal nothing without the key, which is never in the database:
TRIKECERT_CONTACT_DIGEST_KEY, else a file of random bytes beside the signing key file (0600, made
on first use, like the signing key). Changing the key only restarts the limits' short windows.
"""

from __future__ import annotations

import os
import secrets
from functools import lru_cache
from pathlib import Path

from app.config import Settings
from app.trust.keyfile import default_key_path

KEY_FILE_NAME = "trikecert-contact-digest.key"
KEY_BYTES = 32


class DigestKeyUnavailable(RuntimeError):
    """The key file cannot be read or made."""


def digest_key_path(settings: Settings) -> Path:
    """The key file: in the folder of the signing key file (set or default)."""
    return default_key_path(settings).parent / KEY_FILE_NAME


def _make_key_file(path: Path) -> None:
    """Write a new random key to `path` (0600) unless a file is there already (another process won).

    Written whole beside it, then linked into place: a reader never meets a half-written key."""
    path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
    beside = path.with_name(f".{path.name}.{secrets.token_hex(6)}.new")
    handle = os.open(beside, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    try:
        os.write(handle, secrets.token_hex(KEY_BYTES).encode() + b"\n")
        os.fsync(handle)
    finally:
        os.close(handle)
    try:
        os.link(beside, path)  # fails if the path exists: never replaces a key another process made
    except FileExistsError:
        pass
    finally:
        beside.unlink()


@lru_cache(maxsize=8)
def _file_key(path: Path) -> bytes:
    try:
        if not path.exists():
            _make_key_file(path)
        text = path.read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError) as error:
        raise DigestKeyUnavailable(
            f"contact digest key file {path}: cannot read or make it; set TRIKECERT_CONTACT_DIGEST_KEY "
            "or TRIKECERT_SIGNING_KEY_FILE to a folder the service may write (docs/notifications.md)"
        ) from error
    if len(text) < 2 * KEY_BYTES:
        raise DigestKeyUnavailable(f"contact digest key file {path}: shorter than {KEY_BYTES} bytes")
    return text.encode()


def contact_digest_key(settings: Settings) -> bytes:
    """The HMAC key of contact digests: the setting's, else the key file's."""
    if settings.contact_digest_key is not None:
        return settings.contact_digest_key.get_secret_value().encode()
    return _file_key(digest_key_path(settings))
