"""audit_event: each event's client address and request id; the certificates' own history joins the log

Two nullable columns (plain ALTER TABLE ADD COLUMN on both backends). Events recorded before this
revision have neither, and their hash is computed exactly as before (app/audit/chain.py), so the
chain stays intact.

The certificate_audit rows written before the audit log existed (older than its first event, or all of
them on a database with no event yet) are appended to the chain, oldest first, as
`certificate.<issued|reissued|superseded|revoked>` events carrying the row's time, actor and reason
and `imported_from`: every existing row is kept, in both tables. Later certificate_audit rows are
already in the log as the events the service recorded at the time. Nothing is imported twice: an
import is skipped when the log already holds an imported copy of that row.

Revision ID: f4a9c2e7b1d8
Revises: b8d3f1a7c5e2
Create Date: 2026-12-01 23:10:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

from app.audit.chain import GENESIS, EventFields, canonical_json, event_hash

revision: str = "f4a9c2e7b1d8"
down_revision: str | None = "b8d3f1a7c5e2"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

CHAIN_LOCK = 0x7472696B  # the recorder's advisory lock (app/audit/recorder.py)
ACTIONS = {"issue": "issued", "reissue": "reissued", "supersede": "superseded", "revoke": "revoked"}

audit_event = sa.table(
    "audit_event",
    *(
        sa.column(name)
        for name in (
            "id",
            "occurred_at",
            "actor_kind",
            "actor_id",
            "actor_label",
            "action",
            "target_type",
            "target_id",
            "details",
            "previous_hash",
            "hash",
        )
    ),
)


def _as_utc(value: object) -> object:
    from datetime import UTC, datetime

    if isinstance(value, str):  # SQLite hands back text
        value = datetime.fromisoformat(value)
    if isinstance(value, datetime) and value.tzinfo is None:
        value = value.replace(tzinfo=UTC)
    return value


def _import_certificate_history(connection: sa.Connection) -> None:
    if connection.dialect.name == "postgresql":
        connection.execute(sa.text("SELECT pg_advisory_xact_lock(:lock)"), {"lock": CHAIN_LOCK})
    imported = connection.execute(
        sa.text(
            'SELECT count(*) FROM audit_event WHERE details LIKE \'%"imported_from":"certificate_audit"%\''
        )
    ).scalar_one()
    if imported:
        return
    first = connection.execute(sa.text("SELECT min(occurred_at) FROM audit_event")).scalar_one()
    rows = connection.execute(
        sa.text(
            "SELECT a.id, a.action, a.actor, a.at, a.reason, c.number FROM certificate_audit a "
            "JOIN certificate c ON c.id = a.certificate_id ORDER BY a.id"
        )
    ).all()
    first_at = _as_utc(first) if first is not None else None
    older = [row for row in rows if first_at is None or _as_utc(row.at) < first_at]  # type: ignore[operator]
    last = connection.execute(
        sa.text("SELECT id, hash FROM audit_event ORDER BY id DESC LIMIT 1")
    ).one_or_none()
    position, previous = (0, GENESIS) if last is None else (last.id, last.hash)
    for row in older:
        position += 1
        fields = EventFields(
            id=position,
            occurred_at=_as_utc(row.at),  # type: ignore[arg-type]
            actor_kind="imported",
            actor_id=None,
            actor_label=str(row.actor)[:300],
            action=f"certificate.{ACTIONS.get(row.action, row.action)}",
            target_type="certificate",
            target_id=str(row.number)[:64],
            details=canonical_json(
                {"imported_from": "certificate_audit", "row": row.id, "reason": row.reason}
            ),
            previous_hash=previous,
        )
        previous = event_hash(fields)
        values = {name: getattr(fields, name) for name in EventFields.__dataclass_fields__}
        values.pop("client_address")
        values.pop("request_id")
        connection.execute(sa.insert(audit_event).values(**values, hash=previous))


def upgrade() -> None:
    """Apply this revision."""
    op.add_column("audit_event", sa.Column("client_address", sa.String(length=45), nullable=True))
    op.add_column("audit_event", sa.Column("request_id", sa.String(length=64), nullable=True))
    _import_certificate_history(op.get_bind())


def downgrade() -> None:
    """Revert this revision (imported events stay: the log is append-only)."""
    with op.batch_alter_table("audit_event", schema=None) as batch_op:
        batch_op.drop_column("request_id")
        batch_op.drop_column("client_address")
