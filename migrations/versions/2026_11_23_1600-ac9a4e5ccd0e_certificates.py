"""certificates: numbered, immutable, signed; their revocations, audit log, yearly counter and signing keys

Certificates, revocations and audit entries are append-only: triggers refuse any UPDATE, DELETE
(and, on PostgreSQL, TRUNCATE) of them; a signing key can only be retired (active, retired_at).
On SQLite a later batch migration that rebuilds one of these tables drops its triggers: re-create
them in that migration.

Revision ID: ac9a4e5ccd0e
Revises: 5b7e2d9c4a18
Create Date: 2026-11-23 16:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "ac9a4e5ccd0e"
down_revision: str | None = "5b7e2d9c4a18"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

FROZEN_TABLES = ("certificate", "certificate_revocation", "certificate_audit")
KEY_FACTS = ("id", "kid", "public_jwk", "private_pem", "source", "created_at")

POSTGRESQL_FUNCTIONS = """
CREATE FUNCTION trikecert_refuse_change() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    RAISE EXCEPTION 'trikecert: % of % refused: certified records are never changed or deleted',
        TG_OP, TG_TABLE_NAME USING ERRCODE = 'restrict_violation';
END $$;

CREATE FUNCTION trikecert_signing_key_retire_only() RETURNS trigger LANGUAGE plpgsql AS $$
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


def _postgresql_triggers() -> list[str]:
    statements = [POSTGRESQL_FUNCTIONS]
    for table in FROZEN_TABLES:
        statements += [
            f"CREATE TRIGGER immutable_{table} BEFORE UPDATE OR DELETE ON {table} "
            "FOR EACH ROW EXECUTE FUNCTION trikecert_refuse_change()",
            f"CREATE TRIGGER immutable_{table}_truncate BEFORE TRUNCATE ON {table} "
            "FOR EACH STATEMENT EXECUTE FUNCTION trikecert_refuse_change()",
        ]
    statements += [
        "CREATE TRIGGER immutable_signing_key BEFORE UPDATE OR DELETE ON signing_key "
        "FOR EACH ROW EXECUTE FUNCTION trikecert_signing_key_retire_only()",
        "CREATE TRIGGER immutable_signing_key_truncate BEFORE TRUNCATE ON signing_key "
        "FOR EACH STATEMENT EXECUTE FUNCTION trikecert_refuse_change()",
    ]
    return statements


def _sqlite_triggers() -> list[str]:
    statements = []
    for table in FROZEN_TABLES:
        for operation in ("UPDATE", "DELETE"):
            statements.append(
                f"CREATE TRIGGER immutable_{table}_{operation.lower()} BEFORE {operation} ON {table} "
                f"BEGIN SELECT RAISE(ABORT, 'trikecert: {operation} of {table} refused: certified records "
                "are never changed or deleted'); END"
            )
    statements += [
        f"CREATE TRIGGER immutable_signing_key_update BEFORE UPDATE OF {', '.join(KEY_FACTS)} ON signing_key "
        "BEGIN SELECT RAISE(ABORT, 'trikecert: a signing key can only be retired'); END",
        "CREATE TRIGGER immutable_signing_key_delete BEFORE DELETE ON signing_key "
        "BEGIN SELECT RAISE(ABORT, 'trikecert: a signing key is kept for good'); END",
    ]
    return statements


def upgrade() -> None:
    """Apply this revision."""

    op.create_table(
        "certificate_sequence",
        sa.Column("year", sa.Integer(), autoincrement=False, nullable=False),
        sa.Column("last_value", sa.Integer(), nullable=False),
        sa.PrimaryKeyConstraint("year", name=op.f("pk_certificate_sequence")),
    )
    op.create_table(
        "signing_key",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("kid", sa.String(length=32), nullable=False),
        sa.Column("public_jwk", sa.JSON(), nullable=False),
        sa.Column("private_pem", sa.Text(), nullable=True),
        sa.Column("source", sa.String(length=16), nullable=False),
        sa.Column("active", sa.Boolean(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("retired_at", sa.DateTime(timezone=True), nullable=True),
        sa.CheckConstraint("source IN ('database', 'configuration')", name=op.f("ck_signing_key_source")),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_signing_key")),
        sa.UniqueConstraint("kid", name=op.f("uq_signing_key_kid")),
    )
    op.create_table(
        "certificate",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("number", sa.String(length=24), nullable=False),
        sa.Column("year", sa.Integer(), nullable=False),
        sa.Column("sequence", sa.Integer(), nullable=False),
        sa.Column("kind", sa.String(length=16), nullable=False),
        sa.Column("inspection_id", sa.Integer(), nullable=False),
        sa.Column("vehicle_id", sa.Integer(), nullable=False),
        sa.Column("registration_number", sa.String(length=32), nullable=False),
        sa.Column("compliant", sa.Boolean(), nullable=False),
        sa.Column("max_compliant_occupants", sa.Integer(), nullable=False),
        sa.Column("issued_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("expires_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("issued_by", sa.String(length=200), nullable=False),
        sa.Column("issued_by_station_id", sa.Integer(), nullable=True),
        sa.Column("issued_by_user_id", sa.Integer(), nullable=True),
        sa.Column("supersedes_id", sa.Integer(), nullable=True),
        sa.Column("facts", sa.JSON(), nullable=False),
        sa.Column("key_id", sa.String(length=32), nullable=False),
        sa.Column("qr_payload", sa.Text(), nullable=False),
        sa.Column("pdf", sa.LargeBinary(), nullable=False),
        sa.Column("pdf_sha256", sa.String(length=64), nullable=False),
        sa.CheckConstraint("kind IN ('compliant', 'refusal')", name=op.f("ck_certificate_kind")),
        sa.CheckConstraint("expires_at > issued_at", name=op.f("ck_certificate_expiry_after_issue")),
        sa.ForeignKeyConstraint(
            ["inspection_id"], ["inspection.id"], name=op.f("fk_certificate_inspection_id_inspection")
        ),
        sa.ForeignKeyConstraint(
            ["issued_by_station_id"], ["station.id"], name=op.f("fk_certificate_issued_by_station_id_station")
        ),
        sa.ForeignKeyConstraint(
            ["issued_by_user_id"],
            ["user_account.id"],
            name=op.f("fk_certificate_issued_by_user_id_user_account"),
        ),
        sa.ForeignKeyConstraint(
            ["key_id"], ["signing_key.kid"], name=op.f("fk_certificate_key_id_signing_key")
        ),
        sa.ForeignKeyConstraint(
            ["supersedes_id"], ["certificate.id"], name=op.f("fk_certificate_supersedes_id_certificate")
        ),
        sa.ForeignKeyConstraint(
            ["vehicle_id"], ["vehicle.id"], name=op.f("fk_certificate_vehicle_id_vehicle")
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_certificate")),
        sa.UniqueConstraint("number", name=op.f("uq_certificate_number")),
        sa.UniqueConstraint("supersedes_id", name=op.f("uq_certificate_supersedes_id")),
        sa.UniqueConstraint("year", "sequence", name=op.f("uq_certificate_year_sequence")),
    )
    op.create_index(op.f("ix_certificate_inspection_id"), "certificate", ["inspection_id"], unique=False)
    op.create_index(op.f("ix_certificate_vehicle_id"), "certificate", ["vehicle_id"], unique=False)
    op.create_table(
        "certificate_audit",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("certificate_id", sa.Integer(), nullable=False),
        sa.Column("action", sa.String(length=16), nullable=False),
        sa.Column("actor", sa.String(length=200), nullable=False),
        sa.Column("at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("reason", sa.Text(), nullable=True),
        sa.CheckConstraint(
            "action IN ('issue', 'reissue', 'supersede', 'revoke')", name=op.f("ck_certificate_audit_action")
        ),
        sa.ForeignKeyConstraint(
            ["certificate_id"],
            ["certificate.id"],
            name=op.f("fk_certificate_audit_certificate_id_certificate"),
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_certificate_audit")),
    )
    op.create_index(
        op.f("ix_certificate_audit_certificate_id"), "certificate_audit", ["certificate_id"], unique=False
    )
    op.create_table(
        "certificate_revocation",
        sa.Column("certificate_id", sa.Integer(), nullable=False),
        sa.Column("revoked_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("revoked_by", sa.String(length=200), nullable=False),
        sa.Column("reason", sa.Text(), nullable=False),
        sa.CheckConstraint("length(trim(reason)) > 0", name=op.f("ck_certificate_revocation_reason_given")),
        sa.ForeignKeyConstraint(
            ["certificate_id"],
            ["certificate.id"],
            name=op.f("fk_certificate_revocation_certificate_id_certificate"),
        ),
        sa.PrimaryKeyConstraint("certificate_id", name=op.f("pk_certificate_revocation")),
    )
    dialect = op.get_bind().dialect.name
    if dialect == "postgresql":
        for statement in _postgresql_triggers():
            op.execute(statement)
    elif dialect == "sqlite":
        for statement in _sqlite_triggers():
            op.execute(statement)


def downgrade() -> None:
    """Revert this revision (dropping a table drops its triggers)."""

    op.drop_table("certificate_revocation")
    op.drop_index(op.f("ix_certificate_audit_certificate_id"), table_name="certificate_audit")
    op.drop_table("certificate_audit")
    op.drop_index(op.f("ix_certificate_vehicle_id"), table_name="certificate")
    op.drop_index(op.f("ix_certificate_inspection_id"), table_name="certificate")
    op.drop_table("certificate")
    op.drop_table("signing_key")
    op.drop_table("certificate_sequence")
    if op.get_bind().dialect.name == "postgresql":
        op.execute("DROP FUNCTION trikecert_signing_key_retire_only()")
        op.execute("DROP FUNCTION trikecert_refuse_change()")
