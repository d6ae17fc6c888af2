"""statistics: stored counts of closed local days (derived data, not records)

The statistics page counted every inspection of its period on each visit: at 1,000,000 inspections
a year's counts took 265 ms, growing with the history. Inspections and certificates are
append-only, so a local day that has ended never changes: its counts per station and its
certificates are stored once, on the first visit that needs them, and only the open days are
counted live. The rows can be deleted at any time (they are counted again); they hold no record.

Revision ID: 34bfbfad7277
Revises: 5f1549d9de25
Create Date: 2026-12-01 23:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "34bfbfad7277"
down_revision: str | None = "5f1549d9de25"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "statistics_day",
        sa.Column("zone", sa.String(length=64), nullable=False),
        sa.Column("day", sa.Date(), nullable=False),
        sa.Column("starts_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("ends_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("inspections", sa.Integer(), nullable=False),
        sa.Column("compliant", sa.Integer(), nullable=False),
        sa.Column("certificates_issued", sa.Integer(), nullable=False),
        sa.Column("refusals_issued", sa.Integer(), nullable=False),
        sa.Column("certificates_revoked", sa.Integer(), nullable=False),
        sa.PrimaryKeyConstraint("zone", "day", name=op.f("pk_statistics_day")),
    )
    op.create_table(
        "statistics_day_station",
        sa.Column("zone", sa.String(length=64), nullable=False),
        sa.Column("day", sa.Date(), nullable=False),
        sa.Column("station_id", sa.Integer(), autoincrement=False, nullable=False),
        sa.Column("inspections", sa.Integer(), nullable=False),
        sa.Column("compliant", sa.Integer(), nullable=False),
        sa.PrimaryKeyConstraint("zone", "day", "station_id", name=op.f("pk_statistics_day_station")),
    )


def downgrade() -> None:
    """Revert this revision."""
    op.drop_table("statistics_day_station")
    op.drop_table("statistics_day")
