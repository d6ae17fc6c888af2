"""type assessments: a make and model assessed from several vehicles' inspections, kept for good

Three new tables: type_assessment (the model, the settings, the t value and the confident verdict),
type_assessment_inspection (the inspections used, in order) and type_assessment_case (the type's
Table 4 row from the mean readings and the vehicles' spread, per loading case). Like inspections they
are never changed once written: triggers refuse UPDATE and DELETE (and TRUNCATE on PostgreSQL), with
trikecert_refuse_change() from ac9a4e5ccd0e. No existing table changes.

Revision ID: 5f1549d9de25
Revises: a7c3e9f1b5d2
Create Date: 2026-12-01 22:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "5f1549d9de25"
down_revision: str | None = "a7c3e9f1b5d2"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

TABLES = ("type_assessment", "type_assessment_inspection", "type_assessment_case")


def _lsf(name: str, precision: int = 9) -> sa.Column[object]:
    return sa.Column(name, sa.Numeric(precision, 8), nullable=False)


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "type_assessment",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("station_id", sa.Integer(), nullable=True),
        sa.Column("user_id", sa.Integer(), nullable=True),
        sa.Column("make", sa.String(length=80), nullable=False),
        sa.Column("model", sa.String(length=80), nullable=False),
        sa.Column("model_year", sa.Integer(), nullable=True),
        sa.Column("rules_version", sa.String(length=64), nullable=False),
        sa.Column("occupant_mass_kg", sa.Numeric(7, 3), nullable=False),
        sa.Column("wheelbase_m", sa.Numeric(6, 4), nullable=False),
        sa.Column("occupant_config", sa.JSON(), nullable=False),
        sa.Column("confidence", sa.Numeric(4, 3), nullable=False),
        sa.Column("t_value", sa.Numeric(12, 9), nullable=False),
        sa.Column("vehicle_count", sa.Integer(), nullable=False),
        sa.Column("compliant", sa.Boolean(), nullable=False),
        sa.Column("max_compliant_occupants", sa.Integer(), nullable=False),
        sa.ForeignKeyConstraint(
            ["station_id"], ["station.id"], name=op.f("fk_type_assessment_station_id_station")
        ),
        sa.ForeignKeyConstraint(
            ["user_id"], ["user_account.id"], name=op.f("fk_type_assessment_user_id_user_account")
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_type_assessment")),
    )
    op.create_index(
        "ix_type_assessment_make_model_created_at", "type_assessment", ["make", "model", "created_at"]
    )
    op.create_table(
        "type_assessment_inspection",
        sa.Column("type_assessment_id", sa.Integer(), nullable=False),
        sa.Column("position", sa.Integer(), nullable=False),
        sa.Column("inspection_id", sa.Integer(), nullable=False),
        sa.ForeignKeyConstraint(
            ["type_assessment_id"],
            ["type_assessment.id"],
            name=op.f("fk_type_assessment_inspection_type_assessment_id_type_assessment"),
        ),
        sa.ForeignKeyConstraint(
            ["inspection_id"],
            ["inspection.id"],
            name=op.f("fk_type_assessment_inspection_inspection_id_inspection"),
        ),
        sa.PrimaryKeyConstraint("type_assessment_id", "position", name=op.f("pk_type_assessment_inspection")),
    )
    op.create_index(
        op.f("ix_type_assessment_inspection_inspection_id"), "type_assessment_inspection", ["inspection_id"]
    )
    op.create_table(
        "type_assessment_case",
        sa.Column("type_assessment_id", sa.Integer(), nullable=False),
        sa.Column("occupants", sa.Integer(), nullable=False),
        sa.Column("total_kg", sa.Numeric(12, 6), nullable=False),
        sa.Column("rear_kg", sa.Numeric(12, 6), nullable=False),
        _lsf("lsf"),
        _lsf("variance"),
        sa.Column("compliant", sa.Boolean(), nullable=False),
        sa.Column("lsf_exact", sa.String(length=400), nullable=False),
        _lsf("min_lsf"),
        _lsf("mean_lsf"),
        _lsf("max_lsf"),
        _lsf("sd_lsf", 12),
        _lsf("upper_95_lsf", 12),
        sa.Column("confident_compliant", sa.Boolean(), nullable=False),
        sa.ForeignKeyConstraint(
            ["type_assessment_id"],
            ["type_assessment.id"],
            name=op.f("fk_type_assessment_case_type_assessment_id_type_assessment"),
        ),
        sa.PrimaryKeyConstraint("type_assessment_id", "occupants", name=op.f("pk_type_assessment_case")),
    )
    dialect = op.get_bind().dialect.name
    for table in TABLES:
        if dialect == "postgresql":
            op.execute(
                f"CREATE TRIGGER immutable_{table} BEFORE UPDATE OR DELETE ON {table} "
                "FOR EACH ROW EXECUTE FUNCTION trikecert_refuse_change()"
            )
            op.execute(
                f"CREATE TRIGGER immutable_{table}_truncate BEFORE TRUNCATE ON {table} "
                "FOR EACH STATEMENT EXECUTE FUNCTION trikecert_refuse_change()"
            )
        elif dialect == "sqlite":
            for operation in ("UPDATE", "DELETE"):
                op.execute(
                    f"CREATE TRIGGER immutable_{table}_{operation.lower()} BEFORE {operation} ON {table} "
                    f"BEGIN SELECT RAISE(ABORT, 'trikecert: {operation} of {table} refused: a type "
                    "assessment is kept as computed; assess the model again instead'); END"
                )


def downgrade() -> None:
    """Revert this revision (dropping a table drops its triggers)."""
    op.drop_table("type_assessment_case")
    op.drop_index(
        op.f("ix_type_assessment_inspection_inspection_id"), table_name="type_assessment_inspection"
    )
    op.drop_table("type_assessment_inspection")
    op.drop_index("ix_type_assessment_make_model_created_at", table_name="type_assessment")
    op.drop_table("type_assessment")
