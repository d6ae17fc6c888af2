"""sms (issue 23): reminders before a certificate expires, and checks by USSD and SMS

- notification_subscription: a contact (E.164 phone or email) asking for reminders about a vehicle,
  confirmed by a code or link before anything else is sent; deleted with its contact on unsubscribe;
- notification_outbox: every message, written in the transaction that decides to send it; claimed
  by one worker at a time; its recipient erased once sent or given up; pruned after retention;
- notification_check: a digest of the phone and the time of each USSD/SMS check (per-phone limit);
- notification_day: counts by day (subscribed, unsubscribed, sent, failed), no contacts.

Revision ID: c27d3e000003
Revises: bd22e0000001
Create Date: 2026-12-03 19:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c27d3e000003"
down_revision: str | None = "bd22e0000001"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Apply this revision."""
    op.create_table(
        "notification_check",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("phone_digest", sa.String(length=64), nullable=False),
        sa.Column("at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_notification_check")),
    )
    with op.batch_alter_table("notification_check", schema=None) as batch_op:
        batch_op.create_index(batch_op.f("ix_notification_check_at"), ["at"], unique=False)
        batch_op.create_index(
            batch_op.f("ix_notification_check_phone_digest"), ["phone_digest"], unique=False
        )

    op.create_table(
        "notification_day",
        sa.Column("day", sa.Date(), nullable=False),
        sa.Column("what", sa.String(length=16), nullable=False),
        sa.Column("count", sa.Integer(), nullable=False),
        sa.PrimaryKeyConstraint("day", "what", name=op.f("pk_notification_day")),
    )
    op.create_table(
        "notification_subscription",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("vehicle_id", sa.Integer(), nullable=False),
        sa.Column("channel", sa.String(length=8), nullable=False),
        sa.Column("contact", sa.String(length=254), nullable=False),
        sa.Column("contact_digest", sa.String(length=64), nullable=False),
        sa.Column("token", sa.String(length=64), nullable=False),
        sa.Column("code_hash", sa.String(length=64), nullable=True),
        sa.Column("code_failures", sa.Integer(), nullable=False),
        sa.Column("confirmed_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.CheckConstraint("channel IN ('sms', 'email')", name=op.f("ck_notification_subscription_channel")),
        sa.ForeignKeyConstraint(
            ["vehicle_id"], ["vehicle.id"], name=op.f("fk_notification_subscription_vehicle_id_vehicle")
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_notification_subscription")),
        sa.UniqueConstraint("token", name=op.f("uq_notification_subscription_token")),
        sa.UniqueConstraint(
            "vehicle_id",
            "channel",
            "contact",
            name=op.f("uq_notification_subscription_vehicle_id_channel_contact"),
        ),
    )
    with op.batch_alter_table("notification_subscription", schema=None) as batch_op:
        batch_op.create_index(
            batch_op.f("ix_notification_subscription_contact_digest"), ["contact_digest"], unique=False
        )
        batch_op.create_index(
            batch_op.f("ix_notification_subscription_vehicle_id"), ["vehicle_id"], unique=False
        )

    op.create_table(
        "notification_outbox",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("subscription_id", sa.Integer(), nullable=True),
        sa.Column("channel", sa.String(length=8), nullable=False),
        sa.Column("purpose", sa.String(length=16), nullable=False),
        sa.Column("recipient", sa.String(length=254), nullable=True),
        sa.Column("recipient_masked", sa.String(length=64), nullable=False),
        sa.Column("recipient_digest", sa.String(length=64), nullable=False),
        sa.Column("requested_by", sa.String(length=64), nullable=True),
        sa.Column("subject", sa.String(length=200), nullable=True),
        sa.Column("body", sa.Text(), nullable=False),
        sa.Column("unsubscribe_url", sa.String(length=300), nullable=True),
        sa.Column("dedupe_key", sa.String(length=120), nullable=True),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("next_attempt_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("attempts", sa.Integer(), nullable=False),
        sa.Column("claim", sa.String(length=40), nullable=True),
        sa.Column("claimed_until", sa.DateTime(timezone=True), nullable=True),
        sa.Column("sent_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("failed_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("last_error", sa.String(length=300), nullable=True),
        sa.Column("provider_ref", sa.String(length=120), nullable=True),
        sa.CheckConstraint("channel IN ('sms', 'email')", name=op.f("ck_notification_outbox_channel")),
        sa.CheckConstraint(
            "purpose IN ('confirm', 'reminder_30', 'reminder_7', 'reminder_after', 'reply')",
            name=op.f("ck_notification_outbox_purpose"),
        ),
        sa.ForeignKeyConstraint(
            ["subscription_id"],
            ["notification_subscription.id"],
            name=op.f("fk_notification_outbox_subscription_id_notification_subscription"),
            ondelete="SET NULL",
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_notification_outbox")),
        sa.UniqueConstraint("dedupe_key", name=op.f("uq_notification_outbox_dedupe_key")),
    )
    with op.batch_alter_table("notification_outbox", schema=None) as batch_op:
        batch_op.create_index(batch_op.f("ix_notification_outbox_created_at"), ["created_at"], unique=False)
        batch_op.create_index(
            batch_op.f("ix_notification_outbox_recipient_digest"), ["recipient_digest"], unique=False
        )
        batch_op.create_index(
            batch_op.f("ix_notification_outbox_requested_by"), ["requested_by"], unique=False
        )
        batch_op.create_index(
            batch_op.f("ix_notification_outbox_subscription_id"), ["subscription_id"], unique=False
        )


def downgrade() -> None:
    """Revert this revision."""
    with op.batch_alter_table("notification_outbox", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_notification_outbox_subscription_id"))
        batch_op.drop_index(batch_op.f("ix_notification_outbox_requested_by"))
        batch_op.drop_index(batch_op.f("ix_notification_outbox_recipient_digest"))
        batch_op.drop_index(batch_op.f("ix_notification_outbox_created_at"))

    op.drop_table("notification_outbox")
    with op.batch_alter_table("notification_subscription", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_notification_subscription_vehicle_id"))
        batch_op.drop_index(batch_op.f("ix_notification_subscription_contact_digest"))

    op.drop_table("notification_subscription")
    op.drop_table("notification_day")
    with op.batch_alter_table("notification_check", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_notification_check_phone_digest"))
        batch_op.drop_index(batch_op.f("ix_notification_check_at"))

    op.drop_table("notification_check")
