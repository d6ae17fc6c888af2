"""vehicles stations users inspections

Revision ID: 8fd7ad219e95
Revises:
Create Date: 2026-11-23 13:32:22.886168
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "8fd7ad219e95"
down_revision: str | None = None
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""

    op.create_table(
        "station",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("name", sa.String(length=120), nullable=False),
        sa.Column("key_hash", sa.String(length=64), nullable=False),
        sa.Column("key_prefix", sa.String(length=16), nullable=False),
        sa.Column("active", sa.Boolean(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_station")),
        sa.UniqueConstraint("key_hash", name=op.f("uq_station_key_hash")),
        sa.UniqueConstraint("name", name=op.f("uq_station_name")),
    )
    op.create_table(
        "user_account",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("email", sa.String(length=254), nullable=False),
        sa.Column("password_hash", sa.String(length=255), nullable=False),
        sa.Column("role", sa.String(length=16), nullable=False),
        sa.Column("active", sa.Boolean(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.CheckConstraint("role IN ('officer', 'admin')", name=op.f("ck_user_account_role")),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_user_account")),
        sa.UniqueConstraint("email", name=op.f("uq_user_account_email")),
    )
    op.create_table(
        "vehicle",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("registration_number", sa.String(length=32), nullable=False),
        sa.Column("registration_key", sa.String(length=32), nullable=False),
        sa.Column("make", sa.String(length=80), nullable=False),
        sa.Column("model", sa.String(length=80), nullable=False),
        sa.Column("model_year", sa.Integer(), nullable=True),
        sa.Column("chassis_number", sa.String(length=64), nullable=True),
        sa.Column("wheelbase_m", sa.Numeric(precision=6, scale=4), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_vehicle")),
        sa.UniqueConstraint("registration_key", name=op.f("uq_vehicle_registration_key")),
    )
    op.create_table(
        "inspection",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("vehicle_id", sa.Integer(), nullable=False),
        sa.Column("station_id", sa.Integer(), nullable=True),
        sa.Column("user_id", sa.Integer(), nullable=True),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("wheelbase_m", sa.Numeric(precision=6, scale=4), nullable=False),
        sa.Column("occupant_mass_kg", sa.Numeric(precision=7, scale=3), nullable=False),
        sa.Column("sum_tolerance", sa.Numeric(precision=6, scale=4), nullable=False),
        sa.Column("rules_version", sa.String(length=32), nullable=False),
        sa.Column("occupant_config", sa.JSON(), nullable=False),
        sa.Column("front_kg", sa.Numeric(precision=10, scale=4), nullable=False),
        sa.Column("left_rear_kg", sa.Numeric(precision=10, scale=4), nullable=False),
        sa.Column("right_rear_kg", sa.Numeric(precision=10, scale=4), nullable=False),
        sa.Column("overall_kg", sa.Numeric(precision=10, scale=4), nullable=True),
        sa.Column("cg_from_front_m", sa.Numeric(precision=8, scale=5), nullable=False),
        sa.Column("compliant", sa.Boolean(), nullable=False),
        sa.Column("max_compliant_occupants", sa.Integer(), nullable=False),
        sa.ForeignKeyConstraint(
            ["station_id"], ["station.id"], name=op.f("fk_inspection_station_id_station")
        ),
        sa.ForeignKeyConstraint(
            ["user_id"], ["user_account.id"], name=op.f("fk_inspection_user_id_user_account")
        ),
        sa.ForeignKeyConstraint(
            ["vehicle_id"], ["vehicle.id"], name=op.f("fk_inspection_vehicle_id_vehicle")
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_inspection")),
    )
    with op.batch_alter_table("inspection", schema=None) as batch_op:
        batch_op.create_index("ix_inspection_compliant_created_at", ["compliant", "created_at"], unique=False)
        batch_op.create_index(
            "ix_inspection_station_id_created_at", ["station_id", "created_at"], unique=False
        )
        batch_op.create_index(
            "ix_inspection_vehicle_id_created_at", ["vehicle_id", "created_at"], unique=False
        )

    op.create_table(
        "seat",
        sa.Column("vehicle_id", sa.Integer(), nullable=False),
        sa.Column("position", sa.Integer(), nullable=False),
        sa.Column("role", sa.String(length=16), nullable=False),
        sa.Column("x_m", sa.Numeric(precision=6, scale=4), nullable=False),
        sa.CheckConstraint("role IN ('driver', 'passenger')", name=op.f("ck_seat_role")),
        sa.ForeignKeyConstraint(
            ["vehicle_id"],
            ["vehicle.id"],
            name=op.f("fk_seat_vehicle_id_vehicle"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("vehicle_id", "position", name=op.f("pk_seat")),
    )
    op.create_table(
        "loading_case",
        sa.Column("inspection_id", sa.Integer(), nullable=False),
        sa.Column("occupants", sa.Integer(), nullable=False),
        sa.Column("total_kg", sa.Numeric(precision=12, scale=6), nullable=False),
        sa.Column("rear_kg", sa.Numeric(precision=12, scale=6), nullable=False),
        sa.Column("lsf", sa.Numeric(precision=9, scale=8), nullable=False),
        sa.Column("variance", sa.Numeric(precision=9, scale=8), nullable=False),
        sa.Column("compliant", sa.Boolean(), nullable=False),
        sa.Column("measured", sa.Boolean(), nullable=False),
        sa.Column("lsf_exact", sa.String(length=200), nullable=False),
        sa.ForeignKeyConstraint(
            ["inspection_id"],
            ["inspection.id"],
            name=op.f("fk_loading_case_inspection_id_inspection"),
        ),
        sa.PrimaryKeyConstraint("inspection_id", "occupants", name=op.f("pk_loading_case")),
    )
    op.create_table(
        "reading",
        sa.Column("inspection_id", sa.Integer(), nullable=False),
        sa.Column("case_occupants", sa.Integer(), nullable=False),
        sa.Column("wheel", sa.String(length=16), nullable=False),
        sa.Column("sequence", sa.Integer(), nullable=False),
        sa.Column("value_kg", sa.Numeric(precision=10, scale=3), nullable=False),
        sa.CheckConstraint(
            "wheel IN ('front_kg', 'left_rear_kg', 'right_rear_kg', 'overall_kg')",
            name=op.f("ck_reading_wheel"),
        ),
        sa.ForeignKeyConstraint(
            ["inspection_id"], ["inspection.id"], name=op.f("fk_reading_inspection_id_inspection")
        ),
        sa.PrimaryKeyConstraint(
            "inspection_id", "case_occupants", "wheel", "sequence", name=op.f("pk_reading")
        ),
    )


def downgrade() -> None:
    """Revert this revision."""

    op.drop_table("reading")
    op.drop_table("loading_case")
    op.drop_table("seat")
    with op.batch_alter_table("inspection", schema=None) as batch_op:
        batch_op.drop_index("ix_inspection_vehicle_id_created_at")
        batch_op.drop_index("ix_inspection_station_id_created_at")
        batch_op.drop_index("ix_inspection_compliant_created_at")

    op.drop_table("inspection")
    op.drop_table("vehicle")
    op.drop_table("user_account")
    op.drop_table("station")
