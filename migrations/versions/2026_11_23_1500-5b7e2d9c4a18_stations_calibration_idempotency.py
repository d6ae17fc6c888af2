"""stations: scale calibration, idempotency keys and rate-limit windows

Each station gets its location, operator contact and scale (calibration certificate, valid-until
date, capacity, division) and the time its key was last rotated; each inspection records the
calibration in force. New tables: the idempotency keys of the API's POSTs (kept with the first
answer) and one fixed-window request counter per station key.

Revision ID: 5b7e2d9c4a18
Revises: 3c1f6a2b9d47
Create Date: 2026-11-23 15:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "5b7e2d9c4a18"
down_revision: str | None = "3c1f6a2b9d47"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    with op.batch_alter_table("station", schema=None) as batch_op:
        batch_op.add_column(sa.Column("key_rotated_at", sa.DateTime(timezone=True), nullable=True))
        batch_op.add_column(sa.Column("location", sa.String(length=200), nullable=True))
        batch_op.add_column(sa.Column("operator_contact", sa.String(length=200), nullable=True))
        batch_op.add_column(sa.Column("calibration_certificate", sa.String(length=64), nullable=True))
        batch_op.add_column(sa.Column("calibration_valid_until", sa.Date(), nullable=True))
        batch_op.add_column(sa.Column("capacity_kg", sa.Numeric(precision=10, scale=3), nullable=True))
        batch_op.add_column(sa.Column("division_kg", sa.Numeric(precision=8, scale=3), nullable=True))

    with op.batch_alter_table("inspection", schema=None) as batch_op:
        batch_op.add_column(sa.Column("calibration_certificate", sa.String(length=64), nullable=True))
        batch_op.add_column(sa.Column("calibration_valid_until", sa.Date(), nullable=True))

    op.create_table(
        "idempotency_key",
        sa.Column("station_id", sa.Integer(), nullable=False),
        sa.Column("key", sa.String(length=255), nullable=False),
        sa.Column("operation", sa.String(length=64), nullable=False),
        sa.Column("request_hash", sa.String(length=64), nullable=False),
        sa.Column("status_code", sa.Integer(), nullable=False),
        sa.Column("response_body", sa.Text(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(
            ["station_id"],
            ["station.id"],
            name=op.f("fk_idempotency_key_station_id_station"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("station_id", "key", name=op.f("pk_idempotency_key")),
    )
    with op.batch_alter_table("idempotency_key", schema=None) as batch_op:
        batch_op.create_index("ix_idempotency_key_created_at", ["created_at"], unique=False)

    op.create_table(
        "station_rate_window",
        sa.Column("station_id", sa.Integer(), nullable=False),
        sa.Column("window_start", sa.BigInteger(), nullable=False),
        sa.Column("request_count", sa.Integer(), nullable=False),
        sa.ForeignKeyConstraint(
            ["station_id"],
            ["station.id"],
            name=op.f("fk_station_rate_window_station_id_station"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("station_id", name=op.f("pk_station_rate_window")),
    )


def downgrade() -> None:
    """Revert this revision."""
    op.drop_table("station_rate_window")
    with op.batch_alter_table("idempotency_key", schema=None) as batch_op:
        batch_op.drop_index("ix_idempotency_key_created_at")
    op.drop_table("idempotency_key")

    with op.batch_alter_table("inspection", schema=None) as batch_op:
        batch_op.drop_column("calibration_valid_until")
        batch_op.drop_column("calibration_certificate")

    with op.batch_alter_table("station", schema=None) as batch_op:
        batch_op.drop_column("division_kg")
        batch_op.drop_column("capacity_kg")
        batch_op.drop_column("calibration_valid_until")
        batch_op.drop_column("calibration_certificate")
        batch_op.drop_column("operator_contact")
        batch_op.drop_column("location")
        batch_op.drop_column("key_rotated_at")
