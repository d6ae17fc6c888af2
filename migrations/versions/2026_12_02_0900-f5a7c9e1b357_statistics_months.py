"""statistics: per-station sums of whole stored months

A year's per-station sums added up 14,600 stored day rows (40 stations, 366 days) on every visit.
A calendar month whose days are all stored never changes either, so its per-station sums are
stored once too; a period then adds up its whole months and only the days at its two ends. Derived
data like the days: deleting the rows loses nothing.

Revision ID: f5a7c9e1b357
Revises: e3b5c7d9f120
Create Date: 2026-12-02 09:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "f5a7c9e1b357"
down_revision: str | None = "e3b5c7d9f120"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "statistics_month",
        sa.Column("zone", sa.String(length=64), nullable=False),
        sa.Column("month", sa.Date(), nullable=False),
        sa.PrimaryKeyConstraint("zone", "month", name=op.f("pk_statistics_month")),
    )
    op.create_table(
        "statistics_month_station",
        sa.Column("zone", sa.String(length=64), nullable=False),
        sa.Column("month", sa.Date(), nullable=False),
        sa.Column("station_id", sa.Integer(), autoincrement=False, nullable=False),
        sa.Column("inspections", sa.Integer(), nullable=False),
        sa.Column("compliant", sa.Integer(), nullable=False),
        sa.PrimaryKeyConstraint("zone", "month", "station_id", name=op.f("pk_statistics_month_station")),
    )


def downgrade() -> None:
    """Revert this revision."""
    op.drop_table("statistics_month_station")
    op.drop_table("statistics_month")
