"""The app's PostgreSQL role may read and append to the records the law relies on and nothing more:
the whole suite runs as it (tests/conftest.py), and here, after the normal flows worked through
HTTP as that role, every way of rewriting a protected table is refused to it."""

from __future__ import annotations

import os
import subprocess
import sys
import uuid
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from protected_rows import fill_every_protected_table
from sqlalchemy import Connection, Engine, create_engine, text
from sqlalchemy.engine import make_url
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session

from app.db import Base
from app.grants import APPEND_ONLY, PRIVILEGES, AppRoleRefused, grant_app_role

# Each protected table and a column to "rewrite" with itself.
PROTECTED = {
    "inspection": "compliant",
    "reading": "value_kg",
    "loading_case": "lsf",
    "certificate": "kind",
    "certificate_revocation": "reason",
    "certificate_audit": "actor",
    "audit_event": "action",
    "audit_checkpoint": "hash",
    "signing_key": "kid",
    "type_assessment": "compliant",
    "type_assessment_inspection": "inspection_id",
    "type_assessment_case": "upper_95_lsf",
    "vehicle_dynamics_revision": "track_m",
}
TAMPERING = [
    "UPDATE {table} SET {column} = {column}",
    "DELETE FROM {table}",
    "TRUNCATE {table} CASCADE",
    "ALTER TABLE {table} ADD COLUMN forged text",
    "ALTER TABLE {table} DISABLE TRIGGER ALL",
    "ALTER TABLE {table} OWNER TO CURRENT_USER",
    "DROP TABLE {table} CASCADE",
]


def on_postgresql(engine: Engine) -> None:
    if engine.dialect.name != "postgresql":
        pytest.skip("roles and grants are PostgreSQL's; SQLite has only the triggers")


@pytest.fixture
def flows(api: TestClient, client: TestClient, session: Session, engine: Engine) -> dict[str, Any]:
    """As the app role: weigh, certify, revoke, verify, rotate the key; every protected table has rows."""
    on_postgresql(engine)
    body: dict[str, Any] = fill_every_protected_table(api, session, reason="weighed wrongly")["certificate"]
    page = client.get(f"/verify/{body['number']}")
    assert page.status_code == 200
    assert "weighed wrongly" in page.text  # the revocation shows on the public page
    return body


def refused(connection: Connection, sql: str) -> str:
    """Run one statement in its own savepoint; the database's refusal, or fail."""
    with pytest.raises(DBAPIError) as raised, connection.begin_nested():
        connection.execute(text(sql))
    return str(raised.value.orig)


def row_counts(engine: Engine) -> dict[str, int]:
    with engine.connect() as connection:
        return {t: connection.execute(text(f"SELECT count(*) FROM {t}")).scalar_one() for t in PROTECTED}


def test_the_suite_connects_as_an_app_role_that_owns_nothing_and_is_no_superuser(
    engine: Engine, owner_engine: Engine
) -> None:
    on_postgresql(engine)
    with engine.connect() as connection:
        me, superuser = connection.execute(
            text("SELECT current_user, rolsuper FROM pg_roles WHERE rolname = current_user")
        ).one()
        owners = set(connection.scalars(text("SELECT tableowner FROM pg_tables WHERE schemaname = 'public'")))
    with owner_engine.connect() as connection:
        owner = connection.scalar(text("SELECT current_user"))
    assert me != owner
    assert not superuser
    assert owners == {owner}


@pytest.mark.parametrize("table", sorted(PROTECTED))
def test_the_app_role_cannot_rewrite_a_protected_table_in_any_way(
    flows: dict[str, Any], engine: Engine, owner_engine: Engine, table: str
) -> None:
    before = row_counts(owner_engine)
    assert before[table] > 0
    with engine.connect() as connection:
        connection.execute(text("SET lock_timeout = '10s'"))  # never hang on a lock
        for statement in TAMPERING:
            message = refused(connection, statement.format(table=table, column=PROTECTED[table]))
            assert "permission denied" in message or "must be owner" in message, (statement, message)
        connection.rollback()
    assert row_counts(owner_engine) == before


def test_the_app_role_can_neither_create_tables_nor_switch_triggers_off(
    flows: dict[str, Any], engine: Engine
) -> None:
    with engine.connect() as connection:
        assert "permission denied" in refused(connection, "CREATE TABLE forged (id int)")
        assert "permission denied" in refused(connection, "SET session_replication_role = replica")
        assert "permission denied" in refused(connection, "CREATE SCHEMA forged")
        connection.rollback()


def test_a_retired_signing_key_cannot_be_switched_back_on_by_the_app_role(
    flows: dict[str, Any], engine: Engine
) -> None:
    with engine.connect() as connection:
        retired = connection.scalar(text("SELECT kid FROM signing_key WHERE NOT active"))
        assert retired is not None
        message = refused(connection, f"UPDATE signing_key SET active = true WHERE kid = '{retired}'")
        assert "stays retired" in message
        message = refused(connection, "UPDATE signing_key SET retired_at = NULL WHERE NOT active")
        assert "stays retired" in message
        connection.rollback()
    with engine.connect() as connection:
        assert connection.scalar(text("SELECT count(*) FROM signing_key WHERE active")) == 1


def test_every_table_has_its_grant_decided_and_the_records_are_append_only() -> None:
    tables = {table.name for table in Base.metadata.sorted_tables}
    assert set(PRIVILEGES) == tables | {"alembic_version"}
    for table in PROTECTED.keys() - {"signing_key"}:
        assert PRIVILEGES[table] == APPEND_ONLY


def test_granting_refuses_a_superuser_the_owner_itself_and_an_undecided_table(
    engine: Engine, owner_engine: Engine
) -> None:
    on_postgresql(engine)
    with owner_engine.connect() as connection:
        owner = connection.scalar(text("SELECT current_user"))
        app_role = engine.url.username
        assert app_role is not None
        with pytest.raises(AppRoleRefused, match="running the migrations"):
            grant_app_role(connection, owner)
        connection.rollback()
        superuser = connection.scalar(text("SELECT rolname FROM pg_roles WHERE rolsuper LIMIT 1"))
        if superuser != owner:
            with pytest.raises(AppRoleRefused, match="superuser"):
                grant_app_role(connection, superuser)
            connection.rollback()
        connection.execute(text("CREATE TABLE undecided (id int)"))
        with pytest.raises(AppRoleRefused, match="undecided"):
            grant_app_role(connection, app_role)
        connection.rollback()  # the table goes with the transaction
        grant_app_role(connection, app_role)  # granting again is harmless
        connection.commit()
    with engine.connect() as connection:
        allowed = connection.scalar(text("SELECT has_table_privilege('inspection', 'INSERT')"))
        assert allowed
        assert not connection.scalar(text("SELECT has_table_privilege('inspection', 'UPDATE')"))


def test_migrating_as_the_app_role_says_to_migrate_as_the_owner(
    database_url: str, owner_engine: Engine, tmp_path: Path
) -> None:
    on_postgresql(owner_engine)
    name = f"trikecert_scratch_{uuid.uuid4().hex[:12]}"
    admin = create_engine(owner_engine.url, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'CREATE DATABASE "{name}"'))
    try:
        env = {k: v for k, v in os.environ.items() if not k.startswith("TRIKECERT_")}
        env["TRIKECERT_DATABASE_URL"] = (
            make_url(database_url).set(database=name).render_as_string(hide_password=False)
        )
        migrated = subprocess.run(
            [Path(sys.executable).parent / "trikecert", "migrate"],
            env=env,
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
    finally:
        with admin.connect() as connection:
            connection.execute(text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
        admin.dispose()
    assert migrated.returncode == 2
    assert "may not change the schema" in migrated.stderr
    assert "as the owner of the tables" in migrated.stderr
    assert "Traceback" not in migrated.stderr
