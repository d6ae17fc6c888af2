"""The signing key lives outside the database: in a key file (0600) the service makes on first use, or
on a PKCS#11 token. Whoever holds the app's database role reads public keys only; rotation destroys
the key it replaces; an existing database's key is moved out once by the migration."""

from __future__ import annotations

import base64
import json
import os
import stat
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from alembic import command
from certificate_helpers import INSPECTIONS, certify, register, study_certificate, weigh
from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from sqlalchemy import Engine, create_engine, inspect, select, text
from sqlalchemy.engine import make_url
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS

from app import config
from app.cli import main
from app.config import Settings
from app.db import make_engine
from app.migrate import alembic_config, upgrade
from app.trust.keyfile import default_key_path, read_key_file
from app.trust.keys import kid_of, okp_key, public_jwk
from app.trust.models import SigningKey
from app.trust.signer import MemorySigner, private_pem

BEFORE = "a9c3e5f7b201"  # the revision before the key left the database
INSERT_DATABASE_KEY = text(
    "INSERT INTO signing_key (kid, public_jwk, private_pem, source, active, created_at, retired_at) "
    "VALUES (:kid, :jwk, :pem, 'database', :active, '2026-01-01 00:00:00', :retired)"
)


@pytest.fixture
def key_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A key file of this test's own, not made yet (its folder neither)."""
    path = tmp_path / "keys" / "signing.pem"
    monkeypatch.setenv("TRIKECERT_SIGNING_KEY_FILE", str(path))
    config.get_settings.cache_clear()
    yield path
    monkeypatch.undo()
    config.get_settings.cache_clear()


def secrets_of(key: Ed25519PrivateKey) -> list[str]:
    """Every form in which the private key could be stored: PEM lines, the seed in base64 and hex."""
    seed = key.private_bytes(
        serialization.Encoding.Raw, serialization.PrivateFormat.Raw, serialization.NoEncryption()
    )
    pem_body = [line for line in private_pem(key).splitlines() if not line.startswith("-----")]
    return [*pem_body, base64.b64encode(seed).decode(), base64.urlsafe_b64encode(seed).decode(), seed.hex()]


def everything_readable(engine: Engine) -> str:
    """Every value of every table, as the given role reads them, in one string."""
    parts: list[str] = []
    with engine.connect() as connection:
        for table in inspect(connection).get_table_names():
            for row in connection.execute(text(f'SELECT * FROM "{table}"')):
                parts.extend(
                    value.hex() if isinstance(value, bytes) else str(value)
                    for value in row
                    if value is not None
                )
    return "\n".join(parts)


def test_the_key_file_is_made_on_first_use_readable_by_the_service_alone_and_signs(
    key_file: Path, api: TestClient, client: TestClient, capsys: pytest.CaptureFixture[str]
) -> None:
    assert not key_file.exists()
    body = study_certificate(api)
    assert stat.S_IMODE(key_file.stat().st_mode) == 0o600
    assert stat.S_IMODE(key_file.parent.stat().st_mode) == 0o700
    key = read_key_file(key_file)
    assert body["key_id"] == kid_of(okp_key(key))
    published = client.get("/.well-known/trikecert-keys.json").json()["keys"]
    assert [(k["kid"], k["x"]) for k in published] == [(body["key_id"], public_jwk(okp_key(key))["x"])]
    assert client.get(f"/api/v1/verify/{body['number']}").json()["status"] == "refused"
    assert main(["verify", body["qr_payload"]]) == 3  # genuine (1 if not), but a refusal certifies nothing
    assert f"GENUINE: signed by key {body['key_id']}" in capsys.readouterr().out


def test_no_role_of_the_app_can_read_a_private_key_from_the_database(
    key_file: Path, api: TestClient, engine: Engine, session: Session
) -> None:
    study_certificate(api)
    first = read_key_file(key_file)
    assert main(["rotate-signing-key"]) == 0
    keys = [first, read_key_file(key_file)]
    with engine.connect() as connection:
        columns = {c["name"] for c in inspect(connection).get_columns("signing_key")}
        assert columns == {"id", "kid", "public_jwk", "source", "active", "created_at", "retired_at"}
        with pytest.raises(DBAPIError, match="private_pem"):
            connection.execute(text("SELECT private_pem FROM signing_key"))
    stored = everything_readable(engine)  # on PostgreSQL: as the app's own role
    for key in keys:
        for form in secrets_of(key):
            assert form not in stored
    assert [row.source for row in session.scalars(select(SigningKey))] == ["file", "file"]


def test_rotation_retires_the_key_and_destroys_its_private_half(
    key_file: Path, api: TestClient, client: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    first = study_certificate(api)
    old_pem = key_file.read_bytes()
    kept_link = key_file.with_name("old-inode.pem")
    os.link(key_file, kept_link)  # the old file's bytes, as whatever still holds them would read them

    assert main(["rotate-signing-key"]) == 0
    new_kid = capsys.readouterr().out.split()[3].rstrip(";")
    assert new_kid != first["key_id"]
    assert key_file.read_bytes() != old_pem
    assert kid_of(okp_key(read_key_file(key_file))) == new_kid
    assert stat.S_IMODE(key_file.stat().st_mode) == 0o600
    assert kept_link.read_bytes() == b"\0" * len(old_pem)  # overwritten, not only unlinked
    assert [p.name for p in key_file.parent.iterdir() if p != kept_link] == [key_file.name]

    keys = {row.kid: row for row in session.scalars(select(SigningKey))}
    assert not keys[first["key_id"]].active
    assert keys[first["key_id"]].retired_at is not None
    assert keys[new_kid].active
    # Genuine by the retired key's public half, still published (3: genuine, but a refusal; 1: forged)
    assert main(["verify", first["qr_payload"]]) == 3
    assert f"GENUINE: signed by key {first['key_id']}" in capsys.readouterr().out
    assert study_certificate_again(api)["key_id"] == new_kid


def test_a_retired_key_put_back_in_the_file_never_signs_again(key_file: Path, api: TestClient) -> None:
    study_certificate(api)
    old_pem = key_file.read_bytes()
    assert main(["rotate-signing-key"]) == 0
    key_file.write_bytes(old_pem)  # an old backup restored
    refused = api.post(INSPECTIONS, json={"registration_number": "BDG 252 QH", "readings": STUDY_READINGS})
    assert refused.status_code == 201, refused.text
    answer = api.post(f"{INSPECTIONS}/{refused.json()['id']}/certificate")
    assert answer.status_code == 503
    assert "was retired on" in answer.text
    assert "never signs again" in answer.text


def test_a_key_file_that_cannot_be_made_is_named_with_the_setting_to_change(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, api: TestClient
) -> None:
    blocked = tmp_path / "not-a-folder"
    blocked.write_text("a file where the key's folder should be")
    monkeypatch.setenv("TRIKECERT_SIGNING_KEY_FILE", str(blocked / "signing.pem"))
    config.get_settings.cache_clear()
    try:
        register(api)
        answer = api.post(f"{INSPECTIONS}/{weigh(api)}/certificate")
    finally:
        monkeypatch.undo()
        config.get_settings.cache_clear()
    assert answer.status_code == 503
    assert f"signing key file {blocked / 'signing.pem'}" in answer.text
    assert "TRIKECERT_SIGNING_KEY_FILE" in answer.text


def study_certificate_again(api: TestClient) -> dict[str, Any]:
    """The study vehicle weighed once more and certified."""
    return certify(api, weigh(api))


# ---- moving an existing database's key out -------------------------------------------------------


@pytest.fixture
def scratch_engine(tmp_path: Path) -> Iterator[Engine]:
    """An empty database of the run's kind: a temporary SQLite file, or a new PostgreSQL database."""
    server_url = os.environ.get("TRIKECERT_TEST_DATABASE_URL", "")
    if not server_url.startswith("postgresql"):
        engine = make_engine(f"sqlite:///{tmp_path / 'scratch.db'}")
        yield engine
        engine.dispose()
        return
    name = f"trikecert_scratch_{uuid.uuid4().hex[:12]}"
    admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'CREATE DATABASE "{name}"'))
    engine = make_engine(make_url(server_url).set(database=name).render_as_string(hide_password=False))
    try:
        yield engine
    finally:
        engine.dispose()
        with admin.connect() as connection:
            connection.execute(text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
        admin.dispose()


def _database_key(active: bool) -> tuple[Ed25519PrivateKey, dict[str, Any]]:
    key = Ed25519PrivateKey.generate()
    okp = okp_key(key)
    row = {
        "kid": kid_of(okp),
        "jwk": json.dumps(public_jwk(okp)),
        "pem": private_pem(key),
        "active": active,
        "retired": None if active else "2026-06-01 00:00:00",
    }
    return key, row


def test_the_migration_moves_the_active_key_to_the_key_file_once_and_destroys_the_rest(
    scratch_engine: Engine,
    key_file: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    config_ = alembic_config(scratch_engine.url.render_as_string(hide_password=False))
    with scratch_engine.begin() as connection:
        config_.attributes["connection"] = connection
        command.upgrade(config_, BEFORE)
    retired, retired_row = _database_key(active=False)
    active, active_row = _database_key(active=True)
    with scratch_engine.begin() as connection:
        for row in (retired_row, active_row):
            connection.execute(INSERT_DATABASE_KEY, row)
    capsys.readouterr()
    upgrade(scratch_engine)
    said = capsys.readouterr().out
    assert f"moved the active signing key {active_row['kid']} out of the database into {key_file}" in said
    assert "destroyed 1 private key(s) kept in the database" in said
    assert stat.S_IMODE(key_file.stat().st_mode) == 0o600
    assert MemorySigner(read_key_file(key_file), "file").kid == active_row["kid"]
    stored = everything_readable(scratch_engine)
    for key in (retired, active):
        for form in secrets_of(key):
            assert form not in stored
    with scratch_engine.connect() as connection:
        rows = connection.execute(text("SELECT kid, active, source FROM signing_key ORDER BY id")).all()
    assert [tuple(row) for row in rows] == [
        (retired_row["kid"], False, "database"),
        (active_row["kid"], True, "database"),
    ]


def test_with_no_setting_the_key_file_lies_beside_the_sqlite_database(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("TRIKECERT_SIGNING_KEY_FILE", raising=False)
    monkeypatch.chdir(tmp_path)
    beside = Settings(database_url="sqlite:///./data/trikecert.db")
    assert default_key_path(beside) == tmp_path / "data" / "trikecert-signing-key.pem"
    server = Settings(database_url="postgresql+psycopg://app@db:5432/trikecert")
    assert default_key_path(server) == tmp_path / "trikecert-signing-key.pem"
    given = Settings(database_url="sqlite:///./trikecert.db", signing_key_file=tmp_path / "k" / "s.pem")
    assert default_key_path(given) == tmp_path / "k" / "s.pem"
