"""Inspections, readings, loading cases and the certificate tables are append-only, and a retired
signing key stays retired: the ORM refuses it, and the database's triggers refuse raw SQL even from
the tables' owner (SQLite and PostgreSQL alike)."""

from __future__ import annotations

from datetime import timedelta
from decimal import Decimal
from typing import Any

import pytest
from fastapi.testclient import TestClient
from protected_rows import fill_every_protected_table
from sqlalchemy import Engine, delete, select, text, update
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS

from app.certificates.guard import ImmutableRecord
from app.config import get_settings
from app.db import utcnow
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.trust.keys import rotate_signing_key
from app.trust.models import SigningKey

# Each protected table and a column to rewrite.
PROTECTED = {
    "inspection": ("front_kg", "250"),
    "reading": ("value_kg", "1"),
    "loading_case": ("lsf", "0.1"),
    "certificate": ("kind", "'compliant'"),
    "certificate_revocation": ("reason", "'rewritten'"),
    "certificate_audit": ("actor", "'someone else'"),
    "audit_event": ("actor_label", "'someone else'"),
    "audit_checkpoint": ("hash", "'0'"),
    "type_assessment": ("compliant", "true"),
    "type_assessment_inspection": ("inspection_id", "1"),
    "type_assessment_case": ("upper_95_lsf", "0.5"),
    "vehicle_dynamics_revision": ("track_m", "2"),
}


@pytest.fixture
def history(api: TestClient, session: Session) -> dict[str, Any]:
    """A weighing, its refusal revoked, and a key rotated: a row in every protected table."""
    return fill_every_protected_table(api, session, reason="test")


def refused(engine: Engine, sql: str) -> str:
    """The database's refusal of one statement (run as given, then rolled back), or fail."""
    with engine.connect() as connection:
        if engine.dialect.name == "postgresql":
            connection.execute(text("SET lock_timeout = '10s'"))
        with pytest.raises(DBAPIError) as raised:
            connection.execute(text(sql))
        connection.rollback()
    return str(raised.value.orig)


def snapshot(engine: Engine) -> dict[str, list[tuple[Any, ...]]]:
    with engine.connect() as connection:
        return {
            table: [tuple(row) for row in connection.execute(text(f"SELECT * FROM {table} ORDER BY 1"))]
            for table in [*PROTECTED, "signing_key"]
        }


@pytest.mark.parametrize("table", list(PROTECTED))
def test_the_triggers_refuse_to_update_or_delete_a_protected_row(
    history: dict[str, Any], owner_engine: Engine, table: str
) -> None:
    before = snapshot(owner_engine)
    column, value = PROTECTED[table]
    statements = [f"UPDATE {table} SET {column} = {value}", f"DELETE FROM {table}"]
    if owner_engine.dialect.name == "postgresql":
        statements.append(f"TRUNCATE {table} CASCADE")
    for sql in statements:
        assert "trikecert" in refused(owner_engine, sql), sql
    assert snapshot(owner_engine) == before


def test_a_retired_signing_key_stays_retired_in_the_database(
    history: dict[str, Any], owner_engine: Engine
) -> None:
    before = snapshot(owner_engine)
    retired = "(SELECT kid FROM signing_key WHERE NOT active)"
    for sql in [
        f"UPDATE signing_key SET active = true WHERE kid = {retired}",
        f"UPDATE signing_key SET active = true, retired_at = NULL WHERE kid = {retired}",
        f"UPDATE signing_key SET retired_at = NULL WHERE kid = {retired}",
        f"UPDATE signing_key SET retired_at = created_at WHERE kid = {retired}",
        "DELETE FROM signing_key",
    ]:
        assert "trikecert" in refused(owner_engine, sql), sql
    assert snapshot(owner_engine) == before


def test_no_signing_key_is_stored_both_active_and_retired(
    history: dict[str, Any], owner_engine: Engine
) -> None:
    active_and_retired = (
        "INSERT INTO signing_key (kid, public_jwk, source, active, created_at, retired_at) "
        "VALUES ('revived', '{}', 'configuration', true, '2026-01-01', '2026-01-02')"
    )
    assert "trikecert" in refused(owner_engine, active_and_retired)
    current = "(SELECT kid FROM signing_key WHERE active)"
    assert "trikecert" in refused(
        owner_engine, f"UPDATE signing_key SET retired_at = '2026-01-02' WHERE kid = {current}"
    )


def test_the_active_key_can_still_be_retired(history: dict[str, Any], session: Session) -> None:
    rotated = rotate_signing_key(session, get_settings())
    keys = session.scalars(select(SigningKey).order_by(SigningKey.id)).all()
    assert [key.active for key in keys] == [False, False, True]
    assert keys[-1].kid == rotated.kid
    assert all(key.retired_at is not None for key in keys[:-1])


def test_the_orm_refuses_to_change_or_delete_an_inspection_its_readings_or_cases(
    history: dict[str, Any], session: Session
) -> None:
    inspection_id = history["inspection"]["id"]
    inspection = session.get_one(Inspection, inspection_id)
    inspection.front_kg = Decimal("250")
    with pytest.raises(ImmutableRecord, match="kept as measured"):
        session.commit()
    session.rollback()
    session.delete(session.scalars(select(Reading)).first())
    with pytest.raises(ImmutableRecord):
        session.commit()
    session.rollback()
    for model in (Inspection, Reading, LoadingCaseRow):
        with pytest.raises(ImmutableRecord):
            session.execute(delete(model))
    with pytest.raises(ImmutableRecord):
        session.execute(update(Inspection).values(created_at=utcnow() - timedelta(days=1)))
    session.rollback()
    assert session.get_one(Inspection, inspection_id).front_kg == Decimal(str(STUDY_READINGS["front_kg"]))


def test_the_orm_refuses_to_switch_a_retired_key_back_on(history: dict[str, Any], session: Session) -> None:
    retired = session.scalars(select(SigningKey).where(SigningKey.active.is_(False))).one()
    retired.active = True
    with pytest.raises(ImmutableRecord, match="switched back on"):
        session.commit()
    session.rollback()
    retired.retired_at = None
    with pytest.raises(ImmutableRecord, match="switched back on"):
        session.commit()
    session.rollback()
    assert session.scalars(select(SigningKey.kid).where(SigningKey.active.is_(True))).all() != [retired.kid]
