"""vehicles: figures beyond the weighing, one append-only revision per change; inspections name theirs

A new table `vehicle_dynamics_revision` keeps every version of a vehicle's rear track, wheel radius,
seat heights, tyre cornering stiffness and drag (append-only, like the inspections: triggers refuse
UPDATE, DELETE and TRUNCATE). Two nullable columns on `inspection`: the revision it was assessed
with and the CG-height weighing sent with it. Existing vehicles have no revision and existing
inspections none of either, so every row stays readable and their estimates are simply unknown.

Plain ALTER TABLE ADD COLUMN and DROP COLUMN on both backends: the inspection table is never
rebuilt, so its append-only triggers (e5a1c7d93b04) stay. For that reason `dynamics_revision_id`
carries no foreign key (SQLite cannot drop a column that has one without rebuilding the table); the
service only ever stores the id of the revision it has just read, and revisions are never deleted.

Revision ID: 313d2dbefa84
Revises: 34bfbfad7277
Create Date: 2026-12-01 23:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "313d2dbefa84"
down_revision: str | None = "34bfbfad7277"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

TABLE = "vehicle_dynamics_revision"


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        TABLE,
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("vehicle_id", sa.Integer(), nullable=False),
        sa.Column("revision", sa.Integer(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("track_m", sa.Numeric(6, 4), nullable=True),
        sa.Column("wheel_radius_m", sa.Numeric(6, 4), nullable=True),
        sa.Column("seat_heights_m", sa.JSON(), nullable=False),
        sa.Column("front_cornering_stiffness_n_per_rad", sa.Numeric(9, 1), nullable=True),
        sa.Column("rear_cornering_stiffness_n_per_rad", sa.Numeric(9, 1), nullable=True),
        sa.Column("drag_area_m2", sa.Numeric(6, 4), nullable=True),
        sa.Column("centre_of_pressure_height_m", sa.Numeric(6, 4), nullable=True),
        sa.ForeignKeyConstraint(["vehicle_id"], ["vehicle.id"], name=op.f(f"fk_{TABLE}_vehicle_id_vehicle")),
        sa.PrimaryKeyConstraint("id", name=op.f(f"pk_{TABLE}")),
        sa.UniqueConstraint("vehicle_id", "revision", name=op.f(f"uq_{TABLE}_vehicle_id_revision")),
    )
    dialect = op.get_bind().dialect.name
    op.add_column("inspection", sa.Column("dynamics_revision_id", sa.Integer(), nullable=True))
    op.add_column("inspection", sa.Column("dynamics_input", sa.JSON(), nullable=True))
    if dialect == "postgresql":
        op.execute(
            f"CREATE TRIGGER immutable_{TABLE} BEFORE UPDATE OR DELETE ON {TABLE} "
            "FOR EACH ROW EXECUTE FUNCTION trikecert_refuse_change()"
        )
        op.execute(
            f"CREATE TRIGGER immutable_{TABLE}_truncate BEFORE TRUNCATE ON {TABLE} "
            "FOR EACH STATEMENT EXECUTE FUNCTION trikecert_refuse_change()"
        )
    elif dialect == "sqlite":
        for operation in ("UPDATE", "DELETE"):
            op.execute(
                f"CREATE TRIGGER immutable_{TABLE}_{operation.lower()} BEFORE {operation} ON {TABLE} "
                f"BEGIN SELECT RAISE(ABORT, 'trikecert: {operation} of {TABLE} refused: the figures "
                "of a vehicle are kept as given; record a new revision instead'); END"
            )


def downgrade() -> None:
    """Revert this revision."""
    # SQLite (3.35 or later) drops a column in place; the inspection table is not rebuilt.
    op.drop_column("inspection", "dynamics_input")
    op.drop_column("inspection", "dynamics_revision_id")
    op.drop_table(TABLE)
