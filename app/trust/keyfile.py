"""The signing key in a PEM file that only the service's operating-system user can read (0600).

The file holds exactly the key in force. It is made on first use (the newcomer's path needs no
setting), rotation writes the new key beside it and renames it over the old one, and the old key's
bytes are then overwritten with zeros through a handle kept open across the rename: a retired key
is destroyed, and at every moment the path holds one whole, valid key.
"""

from __future__ import annotations

import os
import secrets
from dataclasses import dataclass
from pathlib import Path

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from sqlalchemy.engine import make_url

from app.config import Settings
from app.trust.signer import Handover, KeyUnavailable, MemorySigner, parse_private_key, private_pem

DEFAULT_NAME = "trikecert-signing-key.pem"


def default_key_path(settings: Settings, database_url: str | None = None) -> Path:
    """TRIKECERT_SIGNING_KEY_FILE, else the default: beside the SQLite database file, else in the
    working directory."""
    if settings.signing_key_file is not None:
        return settings.signing_key_file
    url = make_url(database_url or settings.database_url)
    if url.get_backend_name() == "sqlite" and url.database and url.database != ":memory:":
        return Path(url.database).resolve().parent / DEFAULT_NAME
    return Path.cwd() / DEFAULT_NAME


def _unavailable(path: Path, what: str, error: OSError | None = None) -> KeyUnavailable:
    reason = f" ({error.strerror or error})" if error is not None else ""
    return KeyUnavailable(
        f"signing key file {path}: {what}{reason}; set TRIKECERT_SIGNING_KEY_FILE to a file the service "
        "may read and write (see docs/deployment.md)",
        field="signing_key_file",
        rule="unavailable",
    )


def _write_beside(path: Path, pem: str) -> Path:
    """The key written to a new file (0600) in the same folder, synced; its path."""
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        beside = path.with_name(f".{path.name}.{secrets.token_hex(6)}.new")
        handle = os.open(beside, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as error:
        raise _unavailable(path, "cannot write a key in its folder", error) from error
    try:
        os.write(handle, pem.encode())
        os.fsync(handle)
    finally:
        os.close(handle)
    return beside


def _sync_folder(path: Path) -> None:
    folder = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(folder)
    finally:
        os.close(folder)


def _destroy_open(handle: int) -> None:
    """Overwrite a key file's bytes with zeros through an open handle, synced."""
    size = os.fstat(handle).st_size
    os.lseek(handle, 0, os.SEEK_SET)
    os.write(handle, b"\0" * size)
    os.fsync(handle)


def destroy_key_file(path: Path) -> None:
    """Overwrite a key file with zeros and remove it."""
    try:
        handle = os.open(path, os.O_RDWR)
    except FileNotFoundError:
        return
    try:
        _destroy_open(handle)
    finally:
        os.close(handle)
    path.unlink()


def write_new_key_file(path: Path, key: Ed25519PrivateKey) -> bool:
    """Write `key` to `path` (0600) unless a file is there already; True when written."""
    beside = _write_beside(path, private_pem(key))
    try:
        os.link(beside, path)  # fails if the path exists: never overwrites a key another process made
    except FileExistsError:
        return False
    except OSError as error:
        raise _unavailable(path, "cannot create the key file", error) from error
    finally:
        beside.unlink()
    _sync_folder(path)
    return True


def read_key_file(path: Path) -> Ed25519PrivateKey:
    """The key in the file."""
    try:
        text = path.read_text(encoding="ascii")
    except (OSError, UnicodeDecodeError) as error:
        raise _unavailable(path, "cannot read it", error if isinstance(error, OSError) else None) from error
    return parse_private_key(text, setting=f"signing key file {path}")


@dataclass(frozen=True)
class KeyFile:
    """The key store of one PEM file."""

    path: Path

    def describe(self) -> str:
        """The file's path."""
        return str(self.path)

    def current(self) -> MemorySigner:
        """The key in the file; a new key written there first when there is no file yet."""
        if not self.path.exists():
            write_new_key_file(self.path, Ed25519PrivateKey.generate())
        return MemorySigner(read_key_file(self.path), "file")

    def rotate(self, handover: Handover | None = None) -> MemorySigner:
        """A new key renamed over the old, whose bytes are then overwritten with zeros; `handover`
        between the two, while the old key can still sign."""
        new = Ed25519PrivateKey.generate()
        held = MemorySigner(read_key_file(self.path), "file") if self.path.exists() else None
        beside = _write_beside(self.path, private_pem(new))
        if handover is not None:
            try:
                handover(held, MemorySigner(new, "file"))
            except BaseException:
                beside.unlink()
                raise
        try:
            old = os.open(self.path, os.O_RDWR)
        except FileNotFoundError:
            old = None
        except OSError as error:
            beside.unlink()
            raise _unavailable(self.path, "cannot open the key in force to destroy it", error) from error
        try:
            try:
                os.replace(beside, self.path)
            except OSError as error:
                beside.unlink()
                raise _unavailable(self.path, "cannot put the new key in place", error) from error
            _sync_folder(self.path)
            if old is not None:
                _destroy_open(old)
        finally:
            if old is not None:
                os.close(old)
        return MemorySigner(new, "file")
