"""The app's own PostgreSQL role: created if missing and granted exactly what the service does.

Migrations run as the owner of the tables; the service connects as this role, which owns nothing,
is no superuser, may run no DDL, and reads and appends to the records the law relies on without
ever updating, deleting or truncating them. Being no owner, it cannot disable their triggers either.
`grant_app_role` runs in the migration's transaction (`trikecert migrate` with TRIKECERT_APP_DB_ROLE).
"""

from __future__ import annotations

import re

from sqlalchemy import Connection, text

from app.errors import Conflict

APPEND_ONLY = "SELECT, INSERT"
EDITABLE = "SELECT, INSERT, UPDATE"
DISPOSABLE = "SELECT, INSERT, UPDATE, DELETE"

# Every table and what the service does to it; a table missing here stops `trikecert migrate`.
PRIVILEGES: dict[str, str] = {
    "inspection": APPEND_ONLY,
    "reading": APPEND_ONLY,
    "loading_case": APPEND_ONLY,
    "certificate": APPEND_ONLY,
    "certificate_revocation": APPEND_ONLY,
    "certificate_audit": APPEND_ONLY,
    "signing_key": "SELECT, INSERT, UPDATE (active, retired_at)",  # retiring; the trigger keeps it so
    "key_endorsement": APPEND_ONLY,  # signed statements linking keys: a rotation's handover
    "key_withdrawal": APPEND_ONLY,  # a key withdrawn for compromise, signed by the key in force
    "key_grandfathered": "SELECT",  # the keys on record at the migration: written by the owner only
    "certificate_sequence": EDITABLE,  # the yearly counter's upsert
    "vehicle": APPEND_ONLY,  # never updated: the plate is kept as weighed (a trigger refuses a change)
    "vehicle_dynamics_revision": APPEND_ONLY,  # every change of the figures kept
    "seat": DISPOSABLE,  # a vehicle's seats are replaced when it is edited
    "station": EDITABLE,
    "station_rate_window": EDITABLE,  # the per-window counter's upsert
    "user_account": EDITABLE,
    "user_session": DISPOSABLE,  # sign-out and expiry
    "login_attempt": APPEND_ONLY,  # the sign-ins' evidence: nobody rewrites it through the app
    "login_throttle": EDITABLE,  # the per-key count of password checks, bumped by one upsert
    "audit_event": APPEND_ONLY,
    "audit_checkpoint": APPEND_ONLY,  # signed heads of the chain
    "recovery_code": DISPOSABLE,  # a new enrolment or an admin's reset replaces them
    "idempotency_key": DISPOSABLE,  # a failed claim is released; old keys are pruned
    "form_submission": APPEND_ONLY,  # a used form token
    "type_assessment": APPEND_ONLY,  # a make and model assessed: kept as computed
    "type_assessment_inspection": APPEND_ONLY,
    "type_assessment_case": APPEND_ONLY,
    # Derived counts of closed days (app/statistics/models.py), counted again when stale: not records.
    "statistics_day": DISPOSABLE,
    "statistics_day_station": DISPOSABLE,
    "statistics_month": DISPOSABLE,
    "statistics_month_station": DISPOSABLE,
    "statistics_hour": DISPOSABLE,  # and pruned once their days have closed
    "statistics_hour_station": DISPOSABLE,
    # Reminders (app/notifications/): a subscription and its contact are deleted on unsubscribe; an
    # outbox row is claimed, marked sent and has its recipient erased, and is pruned after retention.
    "notification_subscription": DISPOSABLE,
    "notification_outbox": DISPOSABLE,
    "notification_check": DISPOSABLE,  # the per-phone limit's log, pruned after a day
    "notification_day": EDITABLE,  # counts by day, bumped by one upsert
    "notification_phone_language": EDITABLE,  # a phone digest's chosen language, upserted
    "alembic_version": "SELECT",  # /readyz checks the revision
}
ROLE_NAME = re.compile(r"[a-z_][a-z0-9_]{0,62}")

# Role name and password reach the server as settings of this transaction, never inside SQL text,
# so neither needs quoting here nor shows in a statement log.
_CREATE_ROLE = """
DO $$ BEGIN
    EXECUTE format('CREATE ROLE %I LOGIN NOSUPERUSER NOCREATEDB NOCREATEROLE NOREPLICATION NOBYPASSRLS',
                   current_setting('trikecert.app_role'));
EXCEPTION WHEN duplicate_object OR unique_violation THEN NULL;  -- made before, or by a run beside us
END $$
"""
_ALTER_ROLE_LOGIN = """
DO $$ BEGIN
    EXECUTE format('ALTER ROLE %I LOGIN PASSWORD %L',
                   current_setting('trikecert.app_role'), current_setting('trikecert.app_password'));
END $$
"""


class AppRoleRefused(Conflict):
    """The app role asked for would be as powerful as the owner (superuser, owner, member of it)."""


def check_role_name(role: str) -> str:
    """The role name if it is a plain lower-case PostgreSQL identifier, else ValueError."""
    if not ROLE_NAME.fullmatch(role):
        raise ValueError(
            f"the app's database role must be lower-case letters, digits and _ (at most 63), not {role!r}"
        )
    return role


def _refuse(message: str) -> AppRoleRefused:
    return AppRoleRefused(f"TRIKECERT_APP_DB_ROLE: {message}", field="app_db_role", rule="least_privilege")


def _check_not_powerful(connection: Connection, role: str) -> None:
    facts = connection.execute(
        text(
            "SELECT current_user = :role, r.rolsuper OR r.rolbypassrls, "
            "pg_has_role(:role, current_user, 'MEMBER'), "
            "EXISTS (SELECT 1 FROM pg_tables WHERE schemaname = current_schema() AND tableowner = :role) "
            "FROM pg_roles r WHERE r.rolname = :role"
        ),
        {"role": role},
    ).one()
    is_self, superuser, member_of_owner, owns_tables = facts
    if is_self:
        raise _refuse(f"{role} is the role running the migrations; the app needs a role of its own")
    if superuser:
        raise _refuse(f"{role} is a superuser (or bypasses row security); give the app an ordinary role")
    if member_of_owner or owns_tables:
        raise _refuse(f"{role} owns the tables or is a member of their owner; give the app a role of its own")


def _grant_tables(connection: Connection, role: str) -> None:
    tables = set(
        connection.scalars(text("SELECT tablename FROM pg_tables WHERE schemaname = current_schema()"))
    )
    unknown = sorted(tables - PRIVILEGES.keys())
    if unknown:
        raise _refuse(f"no grant decided for table(s) {', '.join(unknown)}: add them to app/grants.py")
    quoted = connection.dialect.identifier_preparer.quote
    schema = quoted(connection.scalar(text("SELECT current_schema()")))
    grantee = quoted(role)
    connection.execute(text(f"REVOKE ALL ON ALL TABLES IN SCHEMA {schema} FROM {grantee}"))
    connection.execute(text(f"REVOKE ALL ON ALL SEQUENCES IN SCHEMA {schema} FROM {grantee}"))
    connection.execute(text(f"REVOKE CREATE ON SCHEMA {schema} FROM {grantee}"))
    connection.execute(text(f"GRANT USAGE ON SCHEMA {schema} TO {grantee}"))
    for table in sorted(tables):
        connection.execute(text(f"GRANT {PRIVILEGES[table]} ON {quoted(table)} TO {grantee}"))
    connection.execute(text(f"GRANT USAGE ON ALL SEQUENCES IN SCHEMA {schema} TO {grantee}"))
    may_create = text("SELECT has_schema_privilege(:role, current_schema(), 'CREATE')")
    if connection.scalar(may_create, {"role": role}):
        # Before PostgreSQL 15 every role may create in the public schema.
        connection.execute(text(f"REVOKE CREATE ON SCHEMA {schema} FROM PUBLIC"))


def grant_app_role(connection: Connection, role: str, *, password: str | None = None) -> None:
    """Create the app's role if missing (with this password, if given) and grant it what the app does."""
    check_role_name(role)
    settings = {"role": role, "password": password or ""}
    connection.execute(
        text(
            "SELECT set_config('trikecert.app_role', :role, true), "
            "set_config('trikecert.app_password', :password, true)"
        ),
        settings,
    )
    connection.execute(text(_CREATE_ROLE))
    if password:
        connection.execute(text(_ALTER_ROLE_LOGIN))
    connection.execute(text("SELECT set_config('trikecert.app_password', '', true)"))
    _check_not_powerful(connection, role)
    quoted = connection.dialect.identifier_preparer.quote
    database = quoted(connection.scalar(text("SELECT current_database()")))
    connection.execute(text(f"GRANT CONNECT ON DATABASE {database} TO {quoted(role)}"))
    _grant_tables(connection, role)
