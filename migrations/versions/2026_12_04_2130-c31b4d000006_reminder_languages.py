"""reminder languages: a subscription's language, and a phone's chosen language by its digest

`notification_subscription.language` (nullable: English for every subscription made before) holds
the language the subscriber asked in, so the confirmation and the reminders speak it.
`notification_phone_language` keeps, per keyed digest of a phone number (never the number), the
language it chose by SMS `LANG` or USSD 4, for its replies and reminder SMS.

Revision ID: c31b4d000006
Revises: c30f7a000005
Create Date: 2026-12-04 21:30:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c31b4d000006"
down_revision: str | None = "c30f7a000005"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Add the column and the table."""
    op.add_column("notification_subscription", sa.Column("language", sa.String(8), nullable=True))
    op.create_table(
        "notification_phone_language",
        sa.Column("phone_digest", sa.String(64), primary_key=True),
        sa.Column("language", sa.String(8), nullable=False),
        sa.Column("chosen_at", sa.DateTime(timezone=True), nullable=False),
    )


def downgrade() -> None:
    """Drop the table and the column."""
    op.drop_table("notification_phone_language")
    op.drop_column("notification_subscription", "language")
