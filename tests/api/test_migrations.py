"""The Alembic migrations are the only way the schema is made, so they must build exactly what the
models describe, and every revision must be reversible: down to an empty database and up again."""

from __future__ import annotations

import json
import os
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from alembic import command
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Engine, create_engine, func, inspect, select, text
from sqlalchemy.engine import make_url
from sqlalchemy.orm import Session

import app.models  # noqa: F401  (registers every table on the metadata)
from app.audit.models import AuditEvent
from app.audit_log.service import verify_log
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, revoke_certificate
from app.config import get_settings
from app.db import Base, make_engine
from app.demo import load_demo
from app.migrate import alembic_config, is_at_head, upgrade

TEST_DATABASE_ENV = "TRIKECERT_TEST_DATABASE_URL"


def differences(engine: Engine) -> list[Any]:
    """What autogenerate would write to bring the database to the models (empty when they agree)."""
    with engine.connect() as connection:
        context = MigrationContext.configure(
            connection,
            opts={"compare_type": True, "render_as_batch": connection.dialect.name == "sqlite"},
        )
        return list(compare_metadata(context, Base.metadata))


def downgrade(engine: Engine, revision: str) -> None:
    """Take the database down to `revision` ("base": nothing left but Alembic's own table)."""
    config = alembic_config(engine.url.render_as_string(hide_password=False))
    with engine.begin() as connection:
        config.attributes["connection"] = connection
        command.downgrade(config, revision)


def tables(engine: Engine) -> set[str]:
    return set(inspect(engine).get_table_names()) - {"alembic_version"}


@pytest.fixture
def scratch_engine(tmp_path: Path) -> Iterator[Engine]:
    """An empty database of the run's kind: a temporary SQLite file, or a new PostgreSQL database."""
    server_url = os.environ.get(TEST_DATABASE_ENV, "")
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


def test_the_migrated_test_database_matches_the_models(engine: Engine) -> None:
    assert is_at_head(engine)
    assert differences(engine) == []


def test_the_migrations_have_a_single_head_and_every_model_table(engine: Engine) -> None:
    script = ScriptDirectory.from_config(alembic_config(str(engine.url)))
    assert len(script.get_heads()) == 1, script.get_heads()
    assert tables(engine) == set(Base.metadata.tables)


def test_every_revision_goes_down_to_an_empty_database_and_back_up(scratch_engine: Engine) -> None:
    upgrade(scratch_engine)
    assert tables(scratch_engine) == set(Base.metadata.tables)

    downgrade(scratch_engine, "base")
    assert tables(scratch_engine) == set()
    assert not is_at_head(scratch_engine)

    upgrade(scratch_engine)
    assert is_at_head(scratch_engine)
    assert differences(scratch_engine) == []


def test_each_revision_steps_down_and_up_one_at_a_time(scratch_engine: Engine) -> None:
    """Walk the history revision by revision, so a downgrade that only works all at once is caught."""
    script = ScriptDirectory.from_config(alembic_config(str(scratch_engine.url)))
    revisions = [r.revision for r in script.walk_revisions()]  # head first
    upgrade(scratch_engine)
    for revision in revisions:
        downgrade(scratch_engine, "-1")
        with scratch_engine.connect() as connection:
            current = MigrationContext.configure(connection).get_current_heads()
        assert revision not in current
    assert tables(scratch_engine) == set()
    upgrade(scratch_engine)
    assert differences(scratch_engine) == []


def test_certificate_history_from_before_the_audit_log_joins_the_chain_once(scratch_engine: Engine) -> None:
    """A database whose certificates were issued before the audit log existed: taken up to head, the
    log holds each certificate_audit row as an event, the chain is intact, and a second pass adds none."""
    upgrade(scratch_engine)
    settings = get_settings()
    with Session(scratch_engine) as session:
        demo = load_demo(session, settings)
        assert demo.inspection is not None
        admin = Actor(label="user:1:admin@example.org", station_id=None, user_id=None, admin=True)
        issued = issue_certificate(session, inspection_id=demo.inspection.id, actor=admin, settings=settings)
        revoke_certificate(session, number=issued.certificate.number, actor=admin, reason="Forged ticket")
        number = issued.certificate.number
    downgrade(scratch_engine, "7e3a9c1d5b20")  # before the audit log: its table goes
    assert "audit_event" not in tables(scratch_engine)
    upgrade(scratch_engine)
    with Session(scratch_engine) as session:
        imported = session.execute(
            select(AuditEvent.action, AuditEvent.target_id, AuditEvent.actor_label, AuditEvent.details)
            .where(AuditEvent.actor_kind == "imported")
            .order_by(AuditEvent.id)
        ).all()
        assert [(row.action, row.target_id) for row in imported] == [
            ("certificate.issued", number),
            ("certificate.revoked", number),
        ]
        assert json.loads(imported[1].details)["reason"] == "Forged ticket"
        assert imported[0].actor_label == "user:1:admin@example.org"
        assert verify_log(session).intact
        count = session.scalar(select(func.count()).select_from(AuditEvent))
    downgrade(scratch_engine, "-1")
    upgrade(scratch_engine)
    with Session(scratch_engine) as session:
        assert session.scalar(select(func.count()).select_from(AuditEvent)) == count
        assert verify_log(session).intact
