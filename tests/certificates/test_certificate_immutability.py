"""Certified records are never changed or deleted: the code refuses it, and so does the database itself
(PostgreSQL and SQLite triggers) when someone tries with raw SQL."""

from __future__ import annotations

from typing import Any

import pytest
from certificate_helpers import study_certificate
from fastapi.testclient import TestClient
from sqlalchemy import Engine, delete, select, text, update
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session

from app.certificates.actors import Actor
from app.certificates.guard import ImmutableRecord
from app.certificates.models import Certificate, CertificateAudit, CertificateRevocation
from app.certificates.records import get_certificate
from app.certificates.service import revoke_certificate
from app.trust.models import SigningKey


@pytest.fixture
def revoked(api: TestClient, session: Session) -> dict[str, Any]:
    body = study_certificate(api)
    revoke_certificate(session, number=body["number"], actor=Actor.of_cli(), reason="test of immutability")
    session.close()  # no transaction left open to hold locks
    return body


def refused_by_database(engine: Engine, sql: str) -> str:
    with engine.begin() as connection:
        if engine.dialect.name == "postgresql":
            connection.execute(text("SET LOCAL lock_timeout = '10s'"))  # never hang on a lock
        with pytest.raises(DBAPIError) as raised:
            connection.execute(text(sql))
        connection.rollback()
    return str(raised.value.orig)


def test_the_orm_refuses_to_change_or_delete_a_certificate(revoked: dict[str, Any], session: Session) -> None:
    certificate = get_certificate(session, revoked["number"])
    certificate.kind = "compliant"
    with pytest.raises(ImmutableRecord):
        session.commit()
    session.rollback()
    session.delete(get_certificate(session, revoked["number"]))
    with pytest.raises(ImmutableRecord):
        session.commit()
    session.rollback()
    assert get_certificate(session, revoked["number"]).kind == "refusal"


@pytest.mark.parametrize("model", [Certificate, CertificateRevocation, CertificateAudit])
def test_the_orm_refuses_bulk_updates_and_deletes(
    revoked: dict[str, Any], session: Session, model: Any
) -> None:
    with pytest.raises(ImmutableRecord):
        session.execute(delete(model))
    with pytest.raises(ImmutableRecord):
        session.execute(update(model).values(**{"reason" if model is not Certificate else "kind": "x"}))
    session.rollback()
    assert session.scalar(select(model).limit(1)) is not None


def test_the_orm_refuses_to_change_a_revocation_or_an_audit_entry(
    revoked: dict[str, Any], session: Session
) -> None:
    revocation = session.scalars(select(CertificateRevocation)).one()
    revocation.reason = "rewritten"
    with pytest.raises(ImmutableRecord):
        session.flush()
    session.rollback()
    entry = session.scalars(select(CertificateAudit).where(CertificateAudit.action == "revoke")).one()
    session.delete(entry)
    with pytest.raises(ImmutableRecord):
        session.flush()
    session.rollback()


@pytest.mark.parametrize(
    "sql",
    [
        "UPDATE certificate SET kind = 'compliant'",
        "UPDATE certificate SET registration_number = 'FAKE 1'",
        "DELETE FROM certificate",
        "UPDATE certificate_revocation SET reason = 'rewritten'",
        "DELETE FROM certificate_revocation",
        "UPDATE certificate_audit SET actor = 'someone else'",
        "DELETE FROM certificate_audit",
        "UPDATE signing_key SET kid = 'forged'",
        "DELETE FROM signing_key",
    ],
)
def test_the_database_refuses_raw_sql_changes(
    revoked: dict[str, Any], owner_engine: Engine, sql: str
) -> None:
    # As the owner, whom no grant stops: the triggers refuse (the app role is refused before them).
    assert "trikecert" in refused_by_database(owner_engine, sql)
    with owner_engine.connect() as connection:
        row = connection.execute(text("SELECT kind, registration_number FROM certificate")).one()
        assert tuple(row) == ("refusal", "BDG 252 QH")
        assert connection.execute(text("SELECT count(*) FROM certificate_audit")).scalar_one() == 2


def test_the_database_refuses_truncate_on_postgresql(revoked: dict[str, Any], owner_engine: Engine) -> None:
    if owner_engine.dialect.name != "postgresql":
        pytest.skip("TRUNCATE exists only on PostgreSQL")
    assert "trikecert" in refused_by_database(owner_engine, "TRUNCATE certificate CASCADE")


def test_a_signing_key_may_be_retired_but_nothing_else(revoked: dict[str, Any], session: Session) -> None:
    key = session.scalars(select(SigningKey)).one()
    key.active = False
    session.commit()
    key.source = "pkcs11"
    with pytest.raises(ImmutableRecord):
        session.commit()
    session.rollback()
    session.delete(key)
    with pytest.raises(ImmutableRecord):
        session.commit()
