"""station_rate_window: UNLOGGED on PostgreSQL (a counter, not a record)

Every signed request bumps its station's row. Logged, each bump wrote WAL and its autocommit waited
for the WAL to reach the disk, with the row locked, so one station's concurrent requests queued
behind each other's fsync. The counts only ever matter within the current window: after a crash
PostgreSQL empties an unlogged table, and the windows open afresh. SQLite has no such tables.

Revision ID: c2d8e4f6a913
Revises: 313d2dbefa84
Create Date: 2026-12-02 05:00:00
"""

from collections.abc import Sequence

from alembic import op

revision: str = "c2d8e4f6a913"
down_revision: str | None = "313d2dbefa84"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    if op.get_bind().dialect.name == "postgresql":
        op.execute("ALTER TABLE station_rate_window SET UNLOGGED")


def downgrade() -> None:
    """Revert this revision."""
    if op.get_bind().dialect.name == "postgresql":
        op.execute("ALTER TABLE station_rate_window SET LOGGED")
