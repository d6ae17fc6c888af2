"""Certified records are never changed or deleted: the code refuses it here, the database by triggers.

The ORM refuses, on every backend, a flush that would update or delete a certificate, a
revocation or an audit entry, and any bulk UPDATE or DELETE aimed at them; a signing key may only
be retired. The migration adds triggers that refuse the same through raw SQL (PostgreSQL and
SQLite). `immutability_lifted` exists for the test fixtures that empty every table.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from sqlalchemy import Connection, event, inspect, text
from sqlalchemy.orm import ORMExecuteState, Session, UOWTransaction

from app.certificates.models import Certificate, CertificateAudit, CertificateRevocation, SigningKey
from app.errors import Conflict

FROZEN: tuple[type[Any], ...] = (Certificate, CertificateRevocation, CertificateAudit)
SIGNING_KEY_MUTABLE = frozenset({"active", "retired_at"})
TRIGGER_PREFIX = "immutable_"


class ImmutableRecord(Conflict):
    """An attempt to change or delete a certified record (409)."""


def _refuse(what: str, verb: str) -> ImmutableRecord:
    return ImmutableRecord(
        f"{what} records are never {verb}; revoke the certificate or issue a new one instead",
        field="certificate",
        rule="immutable",
    )


def changed_columns(instance: object) -> set[str]:
    """The mapped columns of a loaded instance whose value differs from the stored one."""
    state = inspect(instance)
    return {attr.key for attr in state.mapper.column_attrs if state.attrs[attr.key].history.has_changes()}


@event.listens_for(Session, "before_flush")
def _refuse_changes(session: Session, _flush: UOWTransaction, _instances: object) -> None:
    for instance in session.deleted:
        if isinstance(instance, (*FROZEN, SigningKey)):
            raise _refuse(type(instance).__name__, "deleted")
    for instance in session.dirty:
        if isinstance(instance, FROZEN) and changed_columns(instance):
            raise _refuse(type(instance).__name__, "changed")
        if isinstance(instance, SigningKey) and changed_columns(instance) - SIGNING_KEY_MUTABLE:
            raise _refuse("SigningKey", "changed (only retired)")


@event.listens_for(Session, "do_orm_execute")
def _refuse_bulk(state: ORMExecuteState) -> None:
    if not (state.is_update or state.is_delete):
        return
    mapper = state.bind_mapper
    target = mapper.class_ if mapper is not None else None
    if target in FROZEN or (state.is_delete and target is SigningKey):
        raise _refuse(
            target.__name__ if target else "certificate", "deleted" if state.is_delete else "changed"
        )


@contextmanager
def immutability_lifted(connection: Connection) -> Iterator[None]:
    """Let this transaction delete certified rows (test clean-up only; superuser on PostgreSQL)."""
    dialect = connection.dialect.name
    if dialect == "postgresql":
        connection.execute(text("SET LOCAL session_replication_role = replica"))
        yield
        return
    if dialect != "sqlite":
        yield
        return
    triggers = connection.execute(
        text("SELECT name, sql FROM sqlite_master WHERE type = 'trigger' AND name LIKE :prefix"),
        {"prefix": f"{TRIGGER_PREFIX}%"},
    ).all()
    for name, _sql in triggers:
        connection.execute(text(f'DROP TRIGGER "{name}"'))
    try:
        yield
    finally:
        for _name, sql in triggers:
            connection.execute(text(sql))
