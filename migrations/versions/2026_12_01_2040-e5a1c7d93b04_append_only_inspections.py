"""append-only inspections, readings and loading cases; a signing key only moves forward

Inspections, their readings and their loading cases are what a certificate certifies, so they are
kept as they were measured: triggers refuse any UPDATE or DELETE of them (and, on PostgreSQL,
TRUNCATE), as ac9a4e5ccd0e does for the certificate tables. A signing key may still be retired,
but a retired key (inactive, or with a retirement time) can never be switched back on, its
retirement time never changes once set, and no key is stored both active and retired.

These triggers are the second line: on PostgreSQL the app's own role (`TRIKECERT_APP_DB_ROLE`,
see app/grants.py) has no UPDATE, DELETE or TRUNCATE on these tables and does not own them, so it
can neither change them nor disable the triggers. On SQLite a later batch migration that rebuilds
one of these tables drops its triggers: re-create them in that migration.

Revision ID: e5a1c7d93b04
Revises: 9b4d2f7a6c31
Create Date: 2026-12-01 20:00:00
"""

from collections.abc import Sequence

from alembic import op

revision: str = "e5a1c7d93b04"
down_revision: str | None = "9b4d2f7a6c31"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

MEASURED_TABLES = ("inspection", "reading", "loading_case")

# Retired means inactive or carrying a retirement time; either way it stays retired.
_KEY_FORWARD = """
CREATE OR REPLACE FUNCTION trikecert_signing_key_retire_only() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    IF TG_OP = 'INSERT' THEN
        IF NEW.active AND NEW.retired_at IS NOT NULL THEN
            RAISE EXCEPTION 'trikecert: a signing key cannot be stored both active and retired'
                USING ERRCODE = 'restrict_violation';
        END IF;
        RETURN NEW;
    END IF;
    IF TG_OP = 'DELETE'
       OR NEW.id IS DISTINCT FROM OLD.id
       OR NEW.kid IS DISTINCT FROM OLD.kid
       OR NEW.public_jwk::text IS DISTINCT FROM OLD.public_jwk::text
       OR NEW.private_pem IS DISTINCT FROM OLD.private_pem
       OR NEW.source IS DISTINCT FROM OLD.source
       OR NEW.created_at IS DISTINCT FROM OLD.created_at THEN
        RAISE EXCEPTION 'trikecert: % of signing key refused: a key is kept for good and can only be retired',
            TG_OP USING ERRCODE = 'restrict_violation';
    END IF;
    IF NEW.active AND (NOT OLD.active OR OLD.retired_at IS NOT NULL OR NEW.retired_at IS NOT NULL)
       OR (OLD.retired_at IS NOT NULL AND NEW.retired_at IS DISTINCT FROM OLD.retired_at) THEN
        RAISE EXCEPTION 'trikecert: signing key % is retired and stays retired; rotate to a new key instead',
            OLD.kid USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NEW;
END $$;
"""

_KEY_RETIRE_ONLY = """
CREATE OR REPLACE FUNCTION trikecert_signing_key_retire_only() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    IF TG_OP = 'DELETE'
       OR NEW.id IS DISTINCT FROM OLD.id
       OR NEW.kid IS DISTINCT FROM OLD.kid
       OR NEW.public_jwk::text IS DISTINCT FROM OLD.public_jwk::text
       OR NEW.private_pem IS DISTINCT FROM OLD.private_pem
       OR NEW.source IS DISTINCT FROM OLD.source
       OR NEW.created_at IS DISTINCT FROM OLD.created_at THEN
        RAISE EXCEPTION 'trikecert: % of signing key refused: a key is kept for good and can only be retired',
            TG_OP USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NEW;
END $$;
"""

_SQLITE_KEY_TRIGGERS = (
    "CREATE TRIGGER immutable_signing_key_forward BEFORE UPDATE OF active, retired_at ON signing_key "
    "WHEN (NEW.active AND (NOT OLD.active OR OLD.retired_at IS NOT NULL OR NEW.retired_at IS NOT NULL)) "
    "OR (OLD.retired_at IS NOT NULL AND NEW.retired_at IS NOT OLD.retired_at) "
    "BEGIN SELECT RAISE(ABORT, 'trikecert: a retired signing key stays retired; rotate to a new key "
    "instead'); END",
    "CREATE TRIGGER immutable_signing_key_insert BEFORE INSERT ON signing_key "
    "WHEN NEW.active AND NEW.retired_at IS NOT NULL "
    "BEGIN SELECT RAISE(ABORT, 'trikecert: a signing key cannot be stored both active and retired'); END",
)


def _postgresql_upgrade() -> list[str]:
    statements = [_KEY_FORWARD]
    for table in MEASURED_TABLES:
        statements += [
            f"CREATE TRIGGER immutable_{table} BEFORE UPDATE OR DELETE ON {table} "
            "FOR EACH ROW EXECUTE FUNCTION trikecert_refuse_change()",
            f"CREATE TRIGGER immutable_{table}_truncate BEFORE TRUNCATE ON {table} "
            "FOR EACH STATEMENT EXECUTE FUNCTION trikecert_refuse_change()",
        ]
    statements.append(
        "CREATE TRIGGER immutable_signing_key_insert BEFORE INSERT ON signing_key "
        "FOR EACH ROW EXECUTE FUNCTION trikecert_signing_key_retire_only()"
    )
    return statements


def _sqlite_upgrade() -> list[str]:
    statements = []
    for table in MEASURED_TABLES:
        for operation in ("UPDATE", "DELETE"):
            statements.append(
                f"CREATE TRIGGER immutable_{table}_{operation.lower()} BEFORE {operation} ON {table} "
                f"BEGIN SELECT RAISE(ABORT, 'trikecert: {operation} of {table} refused: inspections are "
                "kept as measured; weigh again instead'); END"
            )
    return statements + list(_SQLITE_KEY_TRIGGERS)


def upgrade() -> None:
    """Apply this revision."""
    dialect = op.get_bind().dialect.name
    statements = {"postgresql": _postgresql_upgrade, "sqlite": _sqlite_upgrade}.get(dialect, list)()
    for statement in statements:
        op.execute(statement)


def downgrade() -> None:
    """Revert this revision."""
    dialect = op.get_bind().dialect.name
    if dialect == "postgresql":
        op.execute("DROP TRIGGER immutable_signing_key_insert ON signing_key")
        for table in reversed(MEASURED_TABLES):
            op.execute(f"DROP TRIGGER immutable_{table}_truncate ON {table}")
            op.execute(f"DROP TRIGGER immutable_{table} ON {table}")
        op.execute(_KEY_RETIRE_ONLY)
    elif dialect == "sqlite":
        op.execute("DROP TRIGGER immutable_signing_key_insert")
        op.execute("DROP TRIGGER immutable_signing_key_forward")
        for table in reversed(MEASURED_TABLES):
            op.execute(f"DROP TRIGGER immutable_{table}_delete")
            op.execute(f"DROP TRIGGER immutable_{table}_update")
