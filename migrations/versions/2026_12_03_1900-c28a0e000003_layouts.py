"""axle layouts (helper layouts): delta, tadpole, quadricycle on the vehicle and on every inspection

- `vehicle.layout` ('delta', 'tadpole' or 'quadricycle'; every vehicle on file is a delta). A layout is
  fixed at registration: a trigger refuses to change it in place (a vehicle rebuilt with other axles is
  a new registration), so an inspection can never meet a vehicle whose layout changed under it.
- `inspection.layout`: the layout the weighing was assessed under (every stored row: delta), which must
  be its vehicle's (insert trigger). Its rules version names the limit too (`lsf<1/3:...`).
- Each wheel's mean has its column: the new `left_front_kg`, `right_front_kg` and `rear_kg`; the
  delta's `front_kg`, `left_rear_kg`, `right_rear_kg` may now be null (a wheel the layout lacks).
- `reading.wheel` accepts the new wheels.
- PostgreSQL's certificate trigger re-checks each stored case's verdict from its exact LSF against the
  inspection's layout's limit (it compared with 2/3 alone), so a tadpole's certificate is not refused.

SQLite cannot drop a NOT NULL or change a CHECK without rebuilding the table, which would drop the
append-only triggers of these tables and, for `inspection`, every table that refers to it. The change
loosens constraints only and leaves every stored byte as it is, which SQLite documents as safe to make
by editing the schema text (PRAGMA writable_schema, with the schema version bumped).

Revision ID: c28a0e000003
Revises: c27d3e000003
Create Date: 2026-12-03 19:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c28a0e000003"
down_revision: str | None = "c27d3e000003"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

LAYOUTS = "('delta', 'tadpole', 'quadricycle')"
OLD_WHEELS = "('front_kg', 'left_rear_kg', 'right_rear_kg', 'overall_kg')"
NEW_WHEELS = (
    "('front_kg', 'left_rear_kg', 'right_rear_kg', 'overall_kg', "
    "'left_front_kg', 'right_front_kg', 'rear_kg')"
)
DELTA_WHEELS = ("front_kg", "left_rear_kg", "right_rear_kg")
NEW_COLUMNS = ("left_front_kg", "right_front_kg", "rear_kg")

# The certificate trigger's per-case check, before and after: n_f + n_r tyres times p < n_r times q.
_OLD_CHECK = (
    "3 * split_part(lsf_exact, '/', 1)::numeric\n"
    "               < 2 * coalesce(nullif(split_part(lsf_exact, '/', 2), ''), '1')::numeric"
)
_NEW_CHECK = (
    "(CASE weighed.layout WHEN 'quadricycle' THEN 4 ELSE 3 END) * split_part(lsf_exact, '/', 1)::numeric\n"
    "               < (CASE weighed.layout WHEN 'tadpole' THEN 1 ELSE 2 END)"
    " * coalesce(nullif(split_part(lsf_exact, '/', 2), ''), '1')::numeric"
)

_PG_FUNCTIONS = r"""
CREATE FUNCTION trikecert_inspection_layout() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    IF NEW.layout IS DISTINCT FROM (SELECT layout FROM vehicle WHERE id = NEW.vehicle_id) THEN
        RAISE EXCEPTION 'trikecert: inspection refused: layout % is not that of vehicle %',
            NEW.layout, NEW.vehicle_id USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NEW;
END $$;

CREATE FUNCTION trikecert_vehicle_layout_kept() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    RAISE EXCEPTION 'trikecert: the layout % of vehicle % is fixed at registration; register it anew',
        OLD.layout, OLD.id USING ERRCODE = 'restrict_violation';
END $$;
"""
_PG_TRIGGERS = (
    "CREATE TRIGGER supported_inspection_layout BEFORE INSERT ON inspection "
    "FOR EACH ROW EXECUTE FUNCTION trikecert_inspection_layout()",
    "CREATE TRIGGER immutable_vehicle_layout BEFORE UPDATE OF layout ON vehicle "
    "FOR EACH ROW WHEN (NEW.layout IS DISTINCT FROM OLD.layout) "
    "EXECUTE FUNCTION trikecert_vehicle_layout_kept()",
)
_PG_DROP = (
    "DROP TRIGGER immutable_vehicle_layout ON vehicle",
    "DROP TRIGGER supported_inspection_layout ON inspection",
    "DROP FUNCTION trikecert_vehicle_layout_kept()",
    "DROP FUNCTION trikecert_inspection_layout()",
)
_SQLITE_TRIGGERS = (
    "CREATE TRIGGER supported_inspection_layout BEFORE INSERT ON inspection BEGIN "
    "SELECT RAISE(ABORT, 'trikecert: inspection refused: its layout is not that of its vehicle') "
    "WHERE NEW.layout IS NOT (SELECT layout FROM vehicle WHERE id = NEW.vehicle_id); END",
    "CREATE TRIGGER immutable_vehicle_layout BEFORE UPDATE OF layout ON vehicle "
    "WHEN NEW.layout IS NOT OLD.layout BEGIN "
    "SELECT RAISE(ABORT, 'trikecert: a vehicle''s layout is fixed at registration; register it anew'); END",
)
_SQLITE_DROP = ("DROP TRIGGER immutable_vehicle_layout", "DROP TRIGGER supported_inspection_layout")


def _replace_certificate_check(old: str, new: str) -> None:
    """Rewrite the certificate trigger's function with one check changed (its text read back)."""
    definition = op.get_bind().scalar(
        sa.text("SELECT pg_get_functiondef('trikecert_certificate_supported'::regproc)")
    )
    if old not in definition:
        raise RuntimeError("trikecert_certificate_supported does not hold the check this revision changes")
    op.execute(definition.replace(old, new))


def _edit_sqlite_schema(edits: dict[str, list[tuple[str, str]]]) -> None:
    """Change the schema text of tables in place (constraints loosened only; no stored byte changes)."""
    connection = op.get_bind()
    version = connection.exec_driver_sql("PRAGMA schema_version").scalar_one()
    connection.exec_driver_sql("PRAGMA writable_schema=ON")
    for table, replacements in edits.items():
        sql = connection.exec_driver_sql(
            "SELECT sql FROM sqlite_master WHERE type = 'table' AND name = ?", (table,)
        ).scalar_one()
        for old, new in replacements:
            if old not in sql:
                raise RuntimeError(f"the schema of {table} does not hold {old!r}")
            sql = sql.replace(old, new)
        connection.exec_driver_sql(
            "UPDATE sqlite_master SET sql = ? WHERE type = 'table' AND name = ?", (sql, table)
        )
    connection.exec_driver_sql(f"PRAGMA schema_version={version + 1}")
    connection.exec_driver_sql("PRAGMA writable_schema=OFF")


def upgrade() -> None:
    """Apply this revision."""
    connection = op.get_bind()
    if connection.dialect.name == "postgresql":
        op.add_column(
            "vehicle",
            sa.Column("layout", sa.String(length=16), nullable=False, server_default="delta"),
        )
        op.create_check_constraint(op.f("ck_vehicle_layout"), "vehicle", f"layout IN {LAYOUTS}")
        op.add_column(
            "inspection",
            sa.Column("layout", sa.String(length=16), nullable=False, server_default="delta"),
        )
        for column in NEW_COLUMNS:
            op.add_column("inspection", sa.Column(column, sa.Numeric(precision=10, scale=4), nullable=True))
        for column in DELTA_WHEELS:
            op.alter_column("inspection", column, nullable=True)
        op.drop_constraint(op.f("ck_reading_wheel"), "reading", type_="check")
        op.create_check_constraint(op.f("ck_reading_wheel"), "reading", f"wheel IN {NEW_WHEELS}")
        op.execute(_PG_FUNCTIONS)
        for statement in _PG_TRIGGERS:
            op.execute(statement)
        _replace_certificate_check(_OLD_CHECK, _NEW_CHECK)
        return
    op.execute(
        "ALTER TABLE vehicle ADD COLUMN layout VARCHAR(16) DEFAULT 'delta' NOT NULL "
        f"CONSTRAINT ck_vehicle_layout CHECK (layout IN {LAYOUTS})"
    )
    op.execute("ALTER TABLE inspection ADD COLUMN layout VARCHAR(16) DEFAULT 'delta' NOT NULL")
    for column in NEW_COLUMNS:
        op.execute(f"ALTER TABLE inspection ADD COLUMN {column} NUMERIC(10, 4)")
    _edit_sqlite_schema(
        {
            "inspection": [(f"{c} NUMERIC(10, 4) NOT NULL,", f"{c} NUMERIC(10, 4),") for c in DELTA_WHEELS],
            "reading": [(f"wheel IN {OLD_WHEELS}", f"wheel IN {NEW_WHEELS}")],
        }
    )
    for statement in _SQLITE_TRIGGERS:
        op.execute(statement)


def _refuse_other_layouts() -> None:
    """A downgrade cannot keep a tadpole's or a quadricycle's records: refuse rather than lose them."""
    others = op.get_bind().scalar(sa.text("SELECT count(*) FROM vehicle WHERE layout <> 'delta'"))
    if others:
        raise RuntimeError(f"{others} vehicle(s) are not deltas; their records cannot go below this revision")


def downgrade() -> None:
    """Revert this revision (only while every vehicle on file is a delta)."""
    _refuse_other_layouts()
    if op.get_bind().dialect.name == "postgresql":
        _replace_certificate_check(_NEW_CHECK, _OLD_CHECK)
        for statement in _PG_DROP:
            op.execute(statement)
        op.drop_constraint(op.f("ck_reading_wheel"), "reading", type_="check")
        op.create_check_constraint(op.f("ck_reading_wheel"), "reading", f"wheel IN {OLD_WHEELS}")
        for column in DELTA_WHEELS:
            op.alter_column("inspection", column, nullable=False)
        for column in (*NEW_COLUMNS, "layout"):
            op.drop_column("inspection", column)
        op.drop_constraint(op.f("ck_vehicle_layout"), "vehicle", type_="check")
        op.drop_column("vehicle", "layout")
        return
    for statement in _SQLITE_DROP:
        op.execute(statement)
    _edit_sqlite_schema(
        {
            "inspection": [(f"{c} NUMERIC(10, 4),", f"{c} NUMERIC(10, 4) NOT NULL,") for c in DELTA_WHEELS],
            "reading": [(f"wheel IN {NEW_WHEELS}", f"wheel IN {OLD_WHEELS}")],
        }
    )
    for column in (*NEW_COLUMNS, "layout"):
        op.execute(f"ALTER TABLE inspection DROP COLUMN {column}")
    op.execute("ALTER TABLE vehicle DROP COLUMN layout")
