"""statistics_day_station: an index carrying the counts, for a period's sums per station

A year's per-station sums read 14,600 stored rows, each from the table; with the counts in the
index (PostgreSQL's INCLUDE) they are read from the index alone.

Revision ID: d7e1f3a9b246
Revises: c2d8e4f6a913
Create Date: 2026-12-02 07:00:00
"""

from collections.abc import Sequence

from alembic import op

revision: str = "d7e1f3a9b246"
down_revision: str | None = "c2d8e4f6a913"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.create_index(
        "ix_statistics_day_station_zone_day",
        "statistics_day_station",
        ["zone", "day"],
        postgresql_include=["station_id", "inspections", "compliant"],
    )


def downgrade() -> None:
    """Revert this revision."""
    op.drop_index("ix_statistics_day_station_zone_day", table_name="statistics_day_station")
