"""key endorsements: a signing key is trusted only through signed statements from the key held outside

The app's role could INSERT a `signing_key` row with a public key of its own and certificates signed
with it, and every verification trusted every row. From here a key counts only when it chains to the
key the store holds (a key file, a PKCS#11 token, the configuration): `key_endorsement` keeps the
statements keys sign about each other at a rotation (the old key names its successor, the new key
its predecessor); `key_withdrawal` a key withdrawn for compromise, signed by the key in force;
`key_grandfathered` the keys on record now, which the key in force vouches for on its first start
(app/trust/keys.py). The first two are append-only (triggers on both databases; the app role may read
and insert), the third is written here, by the owner, and the app role may only read it.

Revision ID: bd22e0000001
Revises: c27b2e000002
Create Date: 2026-12-03 19:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "bd22e0000001"
down_revision: str | None = "c27b2e000002"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

TABLES = ("key_endorsement", "key_withdrawal", "key_grandfathered")


def _postgres_triggers(table: str) -> str:
    return f"""
CREATE FUNCTION {table}_refuse_change() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    RAISE EXCEPTION 'trikecert: {table.replace("_", " ")} rows are never changed or deleted'
        USING ERRCODE = 'integrity_constraint_violation';
END $$;
CREATE TRIGGER immutable_{table}_update BEFORE UPDATE OR DELETE ON {table}
    FOR EACH ROW EXECUTE FUNCTION {table}_refuse_change();
CREATE TRIGGER immutable_{table}_truncate BEFORE TRUNCATE ON {table}
    FOR EACH STATEMENT EXECUTE FUNCTION {table}_refuse_change();
"""


def _sqlite_triggers(table: str) -> list[str]:
    message = f"trikecert: {table.replace('_', ' ')} rows are never changed or deleted"
    return [
        f"CREATE TRIGGER immutable_{table}_{verb.lower()} BEFORE {verb} ON {table} "
        f"BEGIN SELECT RAISE(ABORT, '{message}'); END"
        for verb in ("UPDATE", "DELETE")
    ]


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "key_endorsement",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("signer_kid", sa.String(length=32), nullable=False),
        sa.Column("subject_kid", sa.String(length=32), nullable=False),
        sa.Column("relation", sa.String(length=16), nullable=False),
        sa.Column("at", sa.BigInteger(), nullable=False),
        sa.Column("signature", sa.String(length=128), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.CheckConstraint(
            "relation IN ('successor', 'predecessor')", name=op.f("ck_key_endorsement_relation")
        ),
        sa.ForeignKeyConstraint(
            ["signer_kid"], ["signing_key.kid"], name=op.f("fk_key_endorsement_signer_kid_signing_key")
        ),
        sa.ForeignKeyConstraint(
            ["subject_kid"], ["signing_key.kid"], name=op.f("fk_key_endorsement_subject_kid_signing_key")
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_key_endorsement")),
        sa.UniqueConstraint(
            "signer_kid",
            "subject_kid",
            "relation",
            name=op.f("uq_key_endorsement_signer_kid_subject_kid_relation"),
        ),
    )
    op.create_index(op.f("ix_key_endorsement_subject_kid"), "key_endorsement", ["subject_kid"])
    op.create_table(
        "key_withdrawal",
        sa.Column("kid", sa.String(length=32), nullable=False),
        sa.Column("signer_kid", sa.String(length=32), nullable=False),
        sa.Column("at", sa.BigInteger(), nullable=False),
        sa.Column("reason", sa.Text(), nullable=False),
        sa.Column("withdrawn_by", sa.String(length=200), nullable=False),
        sa.Column("signature", sa.String(length=128), nullable=False),
        sa.CheckConstraint("length(trim(reason)) > 0", name=op.f("ck_key_withdrawal_reason_given")),
        sa.ForeignKeyConstraint(["kid"], ["signing_key.kid"], name=op.f("fk_key_withdrawal_kid_signing_key")),
        sa.ForeignKeyConstraint(
            ["signer_kid"], ["signing_key.kid"], name=op.f("fk_key_withdrawal_signer_kid_signing_key")
        ),
        sa.PrimaryKeyConstraint("kid", name=op.f("pk_key_withdrawal")),
    )
    op.create_table(
        "key_grandfathered",
        sa.Column("kid", sa.String(length=32), nullable=False),
        sa.PrimaryKeyConstraint("kid", name=op.f("pk_key_grandfathered")),
    )
    op.execute("INSERT INTO key_grandfathered (kid) SELECT kid FROM signing_key")
    postgres = op.get_bind().dialect.name == "postgresql"
    for table in TABLES:
        if postgres:
            op.execute(_postgres_triggers(table))
        else:
            for statement in _sqlite_triggers(table):
                op.execute(statement)


def downgrade() -> None:
    """Revert this revision."""
    postgres = op.get_bind().dialect.name == "postgresql"
    for table in reversed(TABLES):
        op.drop_table(table)
        if postgres:
            op.execute(f"DROP FUNCTION {table}_refuse_change()")
