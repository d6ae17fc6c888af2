"""front track: a vehicle's figures for the estimates hold the front track of two front wheels

`vehicle_dynamics_revision.front_track_m` (nullable; every stored revision is a delta's or was
recorded before the figure existed, so null): a tadpole or a quadricycle tips about the line through
its outer front and rear contact points, and the front track places that line (reference section 9).
An added nullable column leaves every stored byte and the table's append-only triggers as they are.

Revision ID: c30f7a000005
Revises: c29e1a000004
Create Date: 2026-12-04 20:40:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c30f7a000005"
down_revision: str | None = "c29e1a000004"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Add the column."""
    op.add_column("vehicle_dynamics_revision", sa.Column("front_track_m", sa.Numeric(6, 4), nullable=True))


def downgrade() -> None:
    """Drop the column (SQLite 3.35 and newer drop a column in place)."""
    op.drop_column("vehicle_dynamics_revision", "front_track_m")
