"""statistics: per-station counts of the open days' closed UTC hours

The statistics counted the open day live from the records on every visit: at 13,700 inspections a
day, up to 13,700 index entries a visit by evening, the largest part of a year's page. An hour that
has closed never changes either, so its per-station counts are stored once; the open days then add
up their closed hours and count only the last hour or two live. Derived data like the days:
deleting the rows loses nothing, and hours are pruned once their days have long closed.

Revision ID: a9c3e5f7b201
Revises: f5a7c9e1b357
Create Date: 2026-12-02 11:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "a9c3e5f7b201"
down_revision: str | None = "f5a7c9e1b357"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "statistics_hour",
        sa.Column("starts_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("ends_at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("starts_at", name=op.f("pk_statistics_hour")),
    )
    op.create_table(
        "statistics_hour_station",
        sa.Column("starts_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("station_id", sa.Integer(), autoincrement=False, nullable=False),
        sa.Column("inspections", sa.Integer(), nullable=False),
        sa.Column("compliant", sa.Integer(), nullable=False),
        sa.PrimaryKeyConstraint("starts_at", "station_id", name=op.f("pk_statistics_hour_station")),
    )


def downgrade() -> None:
    """Revert this revision."""
    op.drop_table("statistics_hour_station")
    op.drop_table("statistics_hour")
