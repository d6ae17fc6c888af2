"""Records audit events as part of the same transaction as the change they describe.

One listener on every session's flush turns each new, changed or deleted account, station,
vehicle, signing key, certificate, revocation and sign-in attempt into an event, so no service
function can forget to record one. Who did it is the session's actor: the officer or station the
request was authenticated as (`act_as`); else, outside a request, the process's (the command line);
else anonymous (a request nobody signed in for, even in a process `trikecert serve` started).
Events are chained under a lock (PostgreSQL: a transaction-level advisory lock; SQLite: the writer
lock the flush already holds), so two transactions never append after the same event.
"""

from __future__ import annotations

import getpass
import socket
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from sqlalchemy import Connection, event, insert, inspect, select, text
from sqlalchemy.orm import Session, UOWTransaction

from app.accounts.models import LoginAttempt, User
from app.audit.chain import GENESIS, EventFields, canonical_json, event_hash
from app.audit.models import AuditEvent
from app.certificates.models import Certificate, CertificateRevocation
from app.db import REQUEST_ORIGIN_KEY, utcnow
from app.dynamics.models import DYNAMICS_FIELDS, VehicleDynamicsRevision
from app.stations.models import Station
from app.trust.models import SigningKey
from app.type_assessments.models import TypeAssessmentRecord
from app.vehicles.models import Vehicle

CHAIN_LOCK = 0x7472696B  # "trik": the advisory lock that serialises appends to the chain
ACTOR_KEY = "trikecert_actor"


@dataclass(frozen=True)
class Actor:
    """Who is acting: an officer ("user"), a weighbridge station, the command line, or anonymous."""

    kind: str
    id: int | None
    label: str


ANONYMOUS = Actor("anonymous", None, "not signed in")
_process_actor: Actor | None = None


def act_as(session: Session, actor: Actor) -> None:
    """Record everything this session does from now on as done by `actor`."""
    session.info[ACTOR_KEY] = actor


@contextmanager
def acting_from_command_line() -> Iterator[None]:
    """While a command runs, record what it does without a signed-in actor as done at the command line."""
    global _process_actor
    previous = _process_actor
    _process_actor = Actor("command_line", None, f"{getpass.getuser()}@{socket.gethostname()}")
    try:
        yield
    finally:
        _process_actor = previous


def _actor(session: Session) -> Actor:
    chosen: Actor | None = session.info.get(ACTOR_KEY)
    if chosen is not None:
        return chosen
    if REQUEST_ORIGIN_KEY in session.info:
        # A request's session: `trikecert serve` runs inside the command line's actor, which is not
        # whoever sent the request.
        return ANONYMOUS
    return _process_actor or ANONYMOUS


@dataclass(frozen=True)
class Audited:
    """How one kind of record appears in the audit log."""

    target_type: str
    recorded: tuple[str, ...]  # the columns shown when it is created
    target_id: Callable[[Any], Any]
    secret: frozenset[str] = frozenset()  # columns whose values never enter the log


AUDITED: dict[type[Any], Audited] = {
    User: Audited(
        "user", ("email", "role", "active"), lambda r: r.id, frozenset({"password_hash", "totp_secret"})
    ),
    Station: Audited("station", ("name", "active"), lambda r: r.id, frozenset({"key_hash"})),
    Vehicle: Audited("vehicle", ("registration_number", "make", "model"), lambda r: r.registration_number),
    VehicleDynamicsRevision: Audited(
        "vehicle", ("revision", *DYNAMICS_FIELDS, "seat_heights_m"), lambda r: r.vehicle.registration_number
    ),
    SigningKey: Audited("signing_key", ("kid", "source", "active"), lambda r: r.kid),
    Certificate: Audited("certificate", ("kind", "registration_number", "inspection_id"), lambda r: r.number),
    CertificateRevocation: Audited("certificate", ("reason",), lambda r: r.certificate.number),
    LoginAttempt: Audited("user", ("email", "client_ip"), lambda r: r.user_id),
    TypeAssessmentRecord: Audited(
        "type_assessment", ("make", "model", "model_year", "vehicle_count", "compliant"), lambda r: r.id
    ),
}
# A change of these columns names the event; other changes are "<type>.changed".
NAMED_CHANGES = {"key_hash": "key_rotated", "password_hash": "password_changed", "retired_at": "retired"}


def _value(value: Any) -> Any:
    return value if value is None or isinstance(value, (bool, int, str)) else str(value)


def _created(record: Any, audited: Audited) -> tuple[str, dict[str, Any]]:
    details = {name: _value(getattr(record, name)) for name in audited.recorded}
    if isinstance(record, LoginAttempt):
        return f"sign_in.{record.outcome}", details
    if isinstance(record, Certificate):
        return ("refusal" if record.kind == "refusal" else "certificate") + ".issued", details
    if isinstance(record, CertificateRevocation):
        return "certificate.revoked", details
    if isinstance(record, VehicleDynamicsRevision):
        return "vehicle.dynamics_recorded", details
    return f"{audited.target_type}.created", details


def _changed(record: Any, audited: Audited) -> tuple[str, dict[str, Any]] | None:
    state = inspect(record)
    details: dict[str, Any] = {}
    for attribute in state.mapper.column_attrs:
        history = state.attrs[attribute.key].history
        if not history.has_changes():
            continue
        if attribute.key in audited.secret:
            details[attribute.key] = "(changed)"
        else:
            old = history.deleted[0] if history.deleted else None
            new = history.added[0] if history.added else None
            details[attribute.key] = [_value(old), _value(new)]
    if not details:
        return None
    named = next((NAMED_CHANGES[key] for key in details if key in NAMED_CHANGES), None)
    if "totp_confirmed_at" in details:
        named = "second_factor_enrolled" if details["totp_confirmed_at"][1] else "second_factor_reset"
    elif "totp_secret" in details:
        named = "second_factor_enrolment_started"
    if named is None and "active" in details:
        named = "enabled" if details["active"][1] else "disabled"
    return f"{audited.target_type}.{named or 'changed'}", details


# Their events are written before their rows: the database refuses a certificate or a revocation
# whose event is not there (SQLite checks at the INSERT, having no check at commit).
EVENT_FIRST: tuple[type[Any], ...] = (Certificate, CertificateRevocation)


def _created_events(session: Session, *, first: bool) -> list[tuple[Audited, Any, str, dict[str, Any]]]:
    found: list[tuple[Audited, Any, str, dict[str, Any]]] = []
    for record in session.new:
        audited = AUDITED.get(type(record))
        if audited is not None and isinstance(record, EVENT_FIRST) == first:
            found.append((audited, record, *_created(record, audited)))
    return found


def _events(session: Session) -> list[tuple[Audited, Any, str, dict[str, Any]]]:
    found = _created_events(session, first=False)
    for record in session.dirty:
        audited = AUDITED.get(type(record))
        change = _changed(record, audited) if audited is not None else None
        if audited is not None and change is not None:
            found.append((audited, record, *change))
    for record in session.deleted:
        audited = AUDITED.get(type(record))
        if audited is not None:
            found.append((audited, record, f"{audited.target_type}.deleted", {}))
    return found


def _chain_end(connection: Connection) -> tuple[int, str]:
    if connection.dialect.name == "postgresql":
        connection.execute(text("SELECT pg_advisory_xact_lock(:lock)"), {"lock": CHAIN_LOCK})
    last = connection.execute(
        select(AuditEvent.id, AuditEvent.hash).order_by(AuditEvent.id.desc()).limit(1)
    ).one_or_none()
    return (0, GENESIS) if last is None else (last.id, last.hash)


def record_event(
    session: Session, *, action: str, target_type: str, target_id: object, details: dict[str, Any]
) -> None:
    """Record an event that no stored row shows (a recovery code used, say), in the session's
    current transaction: it is kept only if that transaction commits."""
    _append(session, [(target_type, target_id, action, details)])


@event.listens_for(Session, "before_flush")
def _record_first(session: Session, _flush: UOWTransaction, _instances: object) -> None:
    _append_found(session, _created_events(session, first=True))


@event.listens_for(Session, "after_flush")
def _record(session: Session, _flush: UOWTransaction) -> None:
    _append_found(session, _events(session))


def _append_found(session: Session, found: list[tuple[Audited, Any, str, dict[str, Any]]]) -> None:
    if found:
        _append(
            session,
            [
                (audited.target_type, audited.target_id(record), action, details)
                for audited, record, action, details in found
            ],
        )


def _append(session: Session, items: list[tuple[str, object, str, dict[str, Any]]]) -> None:
    connection = session.connection()
    last_id, previous = _chain_end(connection)
    actor, moment = _actor(session), utcnow()
    client_address, request_id = session.info.get(REQUEST_ORIGIN_KEY, (None, None))
    rows = []
    for position, (target_type, target, action, details) in enumerate(items, start=last_id + 1):
        fields = EventFields(
            id=position,
            occurred_at=moment,
            actor_kind=actor.kind,
            actor_id=actor.id,
            actor_label=actor.label[:300],
            action=action,
            target_type=target_type,
            target_id=None if target is None else str(target)[:64],
            details=canonical_json(details),
            previous_hash=previous,
            client_address=None if client_address is None else str(client_address)[:45],
            request_id=None if request_id is None else str(request_id)[:64],
        )
        previous = event_hash(fields)
        rows.append({**fields.__dict__, "hash": previous})
    connection.execute(insert(AuditEvent), rows)
