"""a paper's second language (helper i18n-pdf): certificate.second_language

- `certificate.second_language` (nullable): the language printed under the English on the paper (ha,
  yo, ig, pcm), or null for English only (every paper issued before). The stored PDF already prints
  it; the column keeps the choice for whatever renders or stamps the paper again.

Adding a nullable column leaves every stored row and the certificate table's append-only triggers as
they are, on SQLite as on PostgreSQL.

Revision ID: c29e1a000004
Revises: c28a0e000003
Create Date: 2026-12-04 20:30:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c29e1a000004"
down_revision: str | None = "c28a0e000003"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None


def upgrade() -> None:
    """Add the nullable column."""
    op.add_column("certificate", sa.Column("second_language", sa.String(length=8), nullable=True))


def downgrade() -> None:
    """Drop it (SQLite 3.35 and later drop a column in place)."""
    op.drop_column("certificate", "second_language")
