"""The signing key on a PKCS#11 token (SoftHSM2, Debian's `softhsm2`, driven by python-pkcs11): made
on the token, never leaving it, signing certificates and audit checkpoints, and destroyed on the
token when it is rotated away."""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from certificate_helpers import certify, study_certificate, weigh
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.audit.models import AuditCheckpoint
from app.cli import main
from app.trust.keys import key_store
from app.trust.models import SigningKey

MODULES = ("/usr/lib/softhsm/libsofthsm2.so", "/usr/lib/x86_64-linux-gnu/softhsm/libsofthsm2.so")
PIN = "4711-trikecert"
LABEL = "trikecert-test"


def _module() -> str | None:
    return next((path for path in MODULES if Path(path).exists()), None)


@dataclass(frozen=True)
class Token:
    module: str
    environment: dict[str, str]


@pytest.fixture(scope="module")
def softhsm(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Token]:
    """A fresh SoftHSM2 token of this module's own, with the service configured to use it."""
    if shutil.which("softhsm2-util") is None or _module() is None:
        pytest.skip("softhsm2-util is not installed (Debian package softhsm2); .ci/run installs it")
    pytest.importorskip("pkcs11", reason="python-pkcs11 is not installed (the test extra has it)")
    folder = tmp_path_factory.mktemp("softhsm")
    (folder / "tokens").mkdir()
    conf = folder / "softhsm2.conf"
    conf.write_text(f"directories.tokendir = {folder / 'tokens'}\nobjectstore.backend = file\n")
    environment = {
        "SOFTHSM2_CONF": str(conf),
        "TRIKECERT_PKCS11_MODULE": str(_module()),
        "TRIKECERT_PKCS11_TOKEN_LABEL": LABEL,
        "TRIKECERT_PKCS11_PIN": PIN,
    }
    subprocess.run(
        ["softhsm2-util", "--init-token", "--free", "--label", LABEL, "--so-pin", "12345678", "--pin", PIN],
        env={**os.environ, **environment},
        check=True,
        capture_output=True,
    )
    previous = {name: os.environ.get(name) for name in environment}
    os.environ.update(environment)
    config.get_settings.cache_clear()
    yield Token(str(_module()), environment)
    for name, value in previous.items():
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value
    config.get_settings.cache_clear()


def token_keys(token: Any) -> list[str]:
    """The labels of the private keys on the token."""
    import pkcs11

    return sorted(
        str(item[pkcs11.Attribute.LABEL])
        for item in token.session.get_objects({pkcs11.Attribute.CLASS: pkcs11.ObjectClass.PRIVATE_KEY})
    )


def test_the_token_signs_certificates_and_checkpoints_and_rotation_destroys_the_old_key(
    softhsm: Token,
    api: TestClient,
    session: Session,
    key_file_untouched: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    import pkcs11

    body = study_certificate(api)
    row = session.scalars(select(SigningKey)).one()
    assert (row.kid, row.source, row.active) == (body["key_id"], "pkcs11", True)
    store: Any = key_store(config.get_settings())
    assert token_keys(store.token) == ["trikecert-signing"]
    private = store.current().private
    assert private[pkcs11.Attribute.SENSITIVE]
    assert not private[pkcs11.Attribute.EXTRACTABLE]  # the token never hands the key out
    assert main(["verify", body["qr_payload"]]) == 3  # genuine (1 if not), but a refusal certifies nothing
    assert f"GENUINE: signed by key {body['key_id']}" in capsys.readouterr().out

    assert main(["audit-verify"]) == 0
    capsys.readouterr()
    checkpoint = session.scalars(select(AuditCheckpoint)).one()
    assert checkpoint.kid == body["key_id"]

    assert main(["rotate-signing-key"]) == 0
    capsys.readouterr()
    session.expire_all()
    keys = {key.kid: key for key in session.scalars(select(SigningKey))}
    new_kid = next(kid for kid, key in keys.items() if key.active)
    assert new_kid != body["key_id"]
    assert not keys[body["key_id"]].active
    assert token_keys(store.token) == ["trikecert-signing"]  # one key: the old one is gone from the token
    assert store.current().kid == new_kid
    assert certify(api, weigh(api))["key_id"] == new_kid
    assert main(["verify", body["qr_payload"]]) == 3  # the old refusal, genuine by its published public key
    assert main(["audit-verify"]) == 0  # the old checkpoint still checks; a new one is signed on the token
    assert not key_file_untouched.exists()


@pytest.fixture
def key_file_untouched() -> Iterator[Path]:
    """The run's key file, which a token-configured service never writes."""
    path = Path(os.environ["TRIKECERT_SIGNING_KEY_FILE"])
    if path.exists():
        path.rename(path.with_name(path.name + ".kept"))
    yield path
    kept = path.with_name(path.name + ".kept")
    if kept.exists():
        kept.rename(path)
