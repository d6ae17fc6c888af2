"""inspection: a vehicle's history read from one index

A vehicle's page of history took its rows from as many table pages as it has inspections (they lie
wherever their days put them). The index now orders them exactly as the page does (newest first,
then by id) and, on PostgreSQL, carries the columns the page shows, so the page is read from the
index alone. (On a large table in production, build it first with CREATE INDEX CONCURRENTLY under
this name; the upgrade then only drops the old one.)

Revision ID: e3b5c7d9f120
Revises: d7e1f3a9b246
Create Date: 2026-12-02 08:00:00
"""

from collections.abc import Sequence

from alembic import op

revision: str = "e3b5c7d9f120"
down_revision: str | None = "d7e1f3a9b246"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

NEW = "ix_inspection_vehicle_history"
OLD = "ix_inspection_vehicle_id_created_at"


def upgrade() -> None:
    """Apply this revision."""
    op.create_index(
        NEW,
        "inspection",
        ["vehicle_id", "created_at", "id"],
        postgresql_include=["compliant", "max_compliant_occupants", "station_id"],
        if_not_exists=True,
    )
    op.drop_index(OLD, table_name="inspection")


def downgrade() -> None:
    """Revert this revision."""
    op.create_index(OLD, "inspection", ["vehicle_id", "created_at"])
    op.drop_index(NEW, table_name="inspection")
