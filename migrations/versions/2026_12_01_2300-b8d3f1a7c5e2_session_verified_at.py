"""accounts: when a browser session last proved who it is (password, and code when enrolled)

What cannot be undone (revoking a certificate, a station's new key, another account's password,
status or second factor) asks for the password and a current code again when this is more than five
minutes old. Sessions open at this revision count from their last check: the second factor's time,
or else the sign-in. Plain ALTER TABLE ADD COLUMN and one UPDATE: no table is rebuilt.

Revision ID: b8d3f1a7c5e2
Revises: 7e3b9c1d5a24
Create Date: 2026-12-01 23:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "b8d3f1a7c5e2"
down_revision: str | None = "7e3b9c1d5a24"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.add_column("user_session", sa.Column("verified_at", sa.DateTime(timezone=True), nullable=True))
    op.execute("UPDATE user_session SET verified_at = COALESCE(second_factor_at, created_at)")


def downgrade() -> None:
    """Revert this revision."""
    with op.batch_alter_table("user_session", schema=None) as batch_op:
        batch_op.drop_column("verified_at")
