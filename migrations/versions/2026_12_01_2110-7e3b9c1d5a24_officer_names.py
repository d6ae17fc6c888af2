"""accounts: an officer's display name and badge number

Documents and officer pages name the officer who recorded a weighing and the one who issued a
certificate by name and badge, never by email. Both columns are nullable: accounts made before
this revision have no name until an administrator gives them one (the pages then say so); new
accounts must have a name. Plain ALTER TABLE ADD COLUMN on both backends: no table is rebuilt.

Revision ID: 7e3b9c1d5a24
Revises: c2f8a4e6b913
Create Date: 2026-12-01 20:30:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "7e3b9c1d5a24"
down_revision: str | None = "c2f8a4e6b913"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.add_column("user_account", sa.Column("display_name", sa.String(length=100), nullable=True))
    op.add_column("user_account", sa.Column("badge_number", sa.String(length=32), nullable=True))


def downgrade() -> None:
    """Revert this revision."""
    with op.batch_alter_table("user_account", schema=None) as batch_op:
        batch_op.drop_column("badge_number")
        batch_op.drop_column("display_name")
