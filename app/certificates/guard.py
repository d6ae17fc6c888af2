"""Certified records are never changed or deleted: the code refuses it here, the database by triggers.

The ORM refuses, on every backend, a flush that would update or delete a certificate, a
revocation, an audit entry, an inspection, a reading or a loading case, and any bulk UPDATE or
DELETE aimed at them; a signing key may only be retired, and a retired key stays retired; a
vehicle's registration is never changed (its inspections and certificates keep it as weighed). The
migrations add triggers that refuse the same through raw SQL (PostgreSQL and SQLite), and on
PostgreSQL the app's role has no UPDATE or DELETE on those tables at all (app/grants.py).
`immutability_lifted` exists for the test fixtures that empty every table or fake a record's age.
"""

from __future__ import annotations

from collections.abc import Collection, Iterator
from contextlib import contextmanager
from typing import Any

from sqlalchemy import Connection, event, inspect, text
from sqlalchemy.orm import ORMExecuteState, Session, UOWTransaction

from app.certificates.models import Certificate, CertificateAudit, CertificateRevocation
from app.errors import Conflict
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.trust.models import SigningKey
from app.vehicles.models import Vehicle

CERTIFIED: tuple[type[Any], ...] = (Certificate, CertificateRevocation, CertificateAudit)
MEASURED: tuple[type[Any], ...] = (Inspection, Reading, LoadingCaseRow)
FROZEN = CERTIFIED + MEASURED
SIGNING_KEY_MUTABLE = frozenset({"active", "retired_at"})
PLATE = frozenset({"registration_number", "registration_key"})  # a vehicle's, kept as weighed
TRIGGER_PREFIX = "immutable_"


class ImmutableRecord(Conflict):
    """An attempt to change or delete a certified record (409)."""


def _refuse(target: type[Any] | None, verb: str) -> ImmutableRecord:
    what = target.__name__ if target is not None else "certificate"
    if target in MEASURED:
        return ImmutableRecord(
            f"{what} records are never {verb}; they are kept as measured, weigh the vehicle again instead",
            field="inspection",
            rule="immutable",
        )
    return ImmutableRecord(
        f"{what} records are never {verb}; revoke the certificate or issue a new one instead",
        field="certificate",
        rule="immutable",
    )


def _retired_key_revived(key: SigningKey) -> bool:
    """True when a flush would switch a retired key back on or move its retirement time."""
    state = inspect(key)
    active, retired_at = state.attrs.active.history, state.attrs.retired_at.history
    was_active = active.deleted[0] if active.deleted else key.active
    was_retired_at = retired_at.deleted[0] if retired_at.deleted else key.retired_at
    if key.active and (not was_active or was_retired_at is not None or key.retired_at is not None):
        return True
    return was_retired_at is not None and key.retired_at != was_retired_at


def changed_columns(instance: object) -> set[str]:
    """The mapped columns of a loaded instance whose value differs from the stored one."""
    state = inspect(instance)
    return {attr.key for attr in state.mapper.column_attrs if state.attrs[attr.key].history.has_changes()}


@event.listens_for(Session, "before_flush")
def _refuse_changes(session: Session, _flush: UOWTransaction, _instances: object) -> None:
    for instance in session.deleted:
        if isinstance(instance, (*FROZEN, SigningKey)):
            raise _refuse(type(instance), "deleted")
    for instance in session.dirty:
        if isinstance(instance, FROZEN) and changed_columns(instance):
            raise _refuse(type(instance), "changed")
        if isinstance(instance, Vehicle) and changed_columns(instance) & PLATE:
            raise ImmutableRecord(
                "registration_number: a vehicle's registration is kept as its inspections weighed it "
                "and is never changed in place",
                field="registration_number",
                rule="immutable",
            )
        if isinstance(instance, SigningKey) and changed_columns(instance) - SIGNING_KEY_MUTABLE:
            raise _refuse(SigningKey, "changed (only retired)")
        if isinstance(instance, SigningKey) and _retired_key_revived(instance):
            raise _refuse(SigningKey, "switched back on once retired")


@event.listens_for(Session, "do_orm_execute")
def _refuse_bulk(state: ORMExecuteState) -> None:
    if not (state.is_update or state.is_delete):
        return
    mapper = state.bind_mapper
    target = mapper.class_ if mapper is not None else None
    if target in FROZEN or (state.is_delete and target is SigningKey):
        raise _refuse(target, "deleted" if state.is_delete else "changed")


@contextmanager
def immutability_lifted(connection: Connection, tables: Collection[str] | None = None) -> Iterator[None]:
    """Let this transaction change or delete frozen rows (test fixtures only; on PostgreSQL the
    connection must be a superuser's: the app's role cannot); on SQLite only `tables`' when given."""
    dialect = connection.dialect.name
    if dialect == "postgresql":
        connection.execute(text("SET LOCAL session_replication_role = replica"))
        yield
        return
    if dialect != "sqlite":
        yield
        return
    # Each trigger dropped and made again changes SQLite's schema, which every other connection
    # then reads again: a fixture that rewrites one table lifts only that table's triggers.
    triggers = [
        (name, sql)
        for name, table, sql in connection.execute(
            text("SELECT name, tbl_name, sql FROM sqlite_master WHERE type = 'trigger' AND name LIKE :p"),
            {"p": f"{TRIGGER_PREFIX}%"},
        )
        if tables is None or table in tables
    ]
    for name, _sql in triggers:
        connection.execute(text(f'DROP TRIGGER "{name}"'))
    try:
        yield
    finally:
        for _name, sql in triggers:
            connection.execute(text(sql))
