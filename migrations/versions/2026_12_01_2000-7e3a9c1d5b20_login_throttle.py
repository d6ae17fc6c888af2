"""login_throttle: password checks counted atomically per email and per client address

Counting failures from the log of attempts left a race: concurrent guesses all read the count
before any of them was recorded. A counter row per key, bumped by one upsert before the password
is verified, decides each check in one atomic step.

Revision ID: 7e3a9c1d5b20
Revises: d41c7e8b2f60
Create Date: 2026-12-01 20:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "7e3a9c1d5b20"
down_revision: str | None = "d41c7e8b2f60"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "login_throttle",
        sa.Column("key", sa.String(length=300), nullable=False),
        sa.Column("checks", sa.Integer(), nullable=False),
        sa.Column("last_counted_at", sa.BigInteger(), nullable=False),
        sa.PrimaryKeyConstraint("key", name=op.f("pk_login_throttle")),
    )


def downgrade() -> None:
    """Revert this revision."""
    op.drop_table("login_throttle")
