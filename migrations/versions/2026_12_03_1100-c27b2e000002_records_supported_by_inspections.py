"""the database refuses a certificate its records do not support; records keep the plate as weighed

An insider with the app's role could INSERT a certificate its inspection never supported, or move a
vehicle's whole history to another plate with one UPDATE. Now, on both databases:

- each inspection keeps the registration as it was weighed (`inspection.registration_number`,
  filled here from the vehicle for the rows already stored), and a new inspection's must be its
  vehicle's;
- a vehicle's registration is never updated in place (trigger; the app never changes it, and on
  PostgreSQL its role has no UPDATE on `vehicle` at all, app/grants.py);
- a certificate row must agree with its inspection: the same vehicle and plate, a kind that
  matches its verdict, and a verdict and occupancy that are those of the inspection's stored
  loading cases (on PostgreSQL each case's verdict is re-checked from its exact LSF too), as must
  the facts it prints (its frozen snapshot: verdict, occupancy, plate, inspection, each case's
  verdict); the
  inspection must be the vehicle's newest (or one that every later weighing of the vehicle agrees
  with, verdict and occupancy alike: so no certificate says more than the newest weighing found),
  never one whose certificate was revoked, and the new certificate must supersede the vehicle's
  current one (and only that one);
- a certificate and a revocation must come with their audit event, naming them. PostgreSQL checks at
  commit (a deferred constraint trigger) that the event, and the certificate_audit rows, were
  written by the same transaction. SQLite has no check at commit and no transaction ids, so there
  the event must be written before the row (app/audit/recorder.py does so) and is checked then.

Errors read "trikecert: ...". The insert triggers are named `supported_*`, so the test fixtures that
lift the `immutable_*` triggers leave them in place; the vehicle's one is `immutable_*`.

Revision ID: c27b2e000002
Revises: c27a1e000001
Create Date: 2026-12-03 11:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c27b2e000002"
down_revision: str | None = "c27a1e000001"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

_BACKFILL = (
    "UPDATE inspection SET registration_number = "
    "(SELECT vehicle.registration_number FROM vehicle WHERE vehicle.id = inspection.vehicle_id)"
)

_PG_FUNCTIONS = r"""
CREATE FUNCTION trikecert_inspection_plate() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    IF NEW.registration_number IS DISTINCT FROM
       (SELECT registration_number FROM vehicle WHERE id = NEW.vehicle_id) THEN
        RAISE EXCEPTION 'trikecert: inspection refused: registration % is not that of vehicle %',
            NEW.registration_number, NEW.vehicle_id USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NEW;
END $$;

CREATE FUNCTION trikecert_vehicle_plate_kept() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    RAISE EXCEPTION 'trikecert: the registration % of vehicle % is kept as weighed, never changed in place',
        OLD.registration_number, OLD.id USING ERRCODE = 'restrict_violation';
END $$;

CREATE FUNCTION trikecert_certificate_supported() RETURNS trigger LANGUAGE plpgsql AS $$
DECLARE
    weighed inspection%ROWTYPE;
    cases integer;
    cases_compliant boolean;
    first_failing integer;
    best integer;
    wrong_cases integer;
    current_id integer;
BEGIN
    IF (NEW.kind = 'compliant') IS DISTINCT FROM NEW.compliant THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: kind % does not match its verdict (compliant %)',
            NEW.number, NEW.kind, NEW.compliant USING ERRCODE = 'restrict_violation';
    END IF;
    SELECT * INTO weighed FROM inspection WHERE id = NEW.inspection_id;
    IF NOT FOUND THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: inspection % is not on record',
            NEW.number, NEW.inspection_id USING ERRCODE = 'restrict_violation';
    END IF;
    IF weighed.vehicle_id IS DISTINCT FROM NEW.vehicle_id
       OR weighed.registration_number IS DISTINCT FROM NEW.registration_number THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: vehicle % (%) is not what inspection % weighed: %',
            NEW.number, NEW.vehicle_id, NEW.registration_number, weighed.id, weighed.registration_number
            USING ERRCODE = 'restrict_violation';
    END IF;
    SELECT count(*), bool_and(compliant),
           min(occupants) FILTER (WHERE occupants >= 1 AND NOT compliant),
           count(*) FILTER (WHERE compliant IS DISTINCT FROM (
               3 * split_part(lsf_exact, '/', 1)::numeric
               < 2 * coalesce(nullif(split_part(lsf_exact, '/', 2), ''), '1')::numeric))
      INTO cases, cases_compliant, first_failing, wrong_cases
      FROM loading_case WHERE inspection_id = weighed.id;
    SELECT coalesce(max(occupants), 0) INTO best FROM loading_case
     WHERE inspection_id = weighed.id AND occupants >= 1
       AND (first_failing IS NULL OR occupants < first_failing);
    IF cases = 0 OR wrong_cases > 0
       OR NEW.compliant IS DISTINCT FROM cases_compliant OR weighed.compliant IS DISTINCT FROM cases_compliant
       OR NEW.max_compliant_occupants IS DISTINCT FROM best
       OR weighed.max_compliant_occupants IS DISTINCT FROM best THEN
        RAISE EXCEPTION
            'trikecert: % refused: compliant %, % occupants; the loading cases of inspection % say %, %',
            NEW.number, NEW.compliant, NEW.max_compliant_occupants, weighed.id,
            coalesce(cases_compliant, false), best USING ERRCODE = 'restrict_violation';
    END IF;
    IF (NEW.facts ->> 'compliant')::boolean IS DISTINCT FROM NEW.compliant
       OR (NEW.facts ->> 'max_compliant_occupants')::integer IS DISTINCT FROM NEW.max_compliant_occupants
       OR NEW.facts -> 'vehicle' ->> 'registration_number' IS DISTINCT FROM NEW.registration_number
       OR (NEW.facts -> 'inspection' ->> 'id')::integer IS DISTINCT FROM weighed.id
       OR json_array_length(NEW.facts -> 'cases') IS DISTINCT FROM cases
       OR EXISTS (SELECT 1 FROM json_array_elements(NEW.facts -> 'cases') printed
                  WHERE NOT EXISTS (SELECT 1 FROM loading_case stored WHERE stored.inspection_id = weighed.id
                                    AND stored.occupants = (printed ->> 'occupants')::integer
                                    AND stored.compliant = (printed ->> 'compliant')::boolean)) THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: the facts it prints are not those of inspection %',
            NEW.number, weighed.id USING ERRCODE = 'restrict_violation';
    END IF;
    IF EXISTS (SELECT 1 FROM inspection later WHERE later.vehicle_id = weighed.vehicle_id
               AND (later.created_at, later.id) > (weighed.created_at, weighed.id)
               AND (later.compliant, later.max_compliant_occupants)
                   IS DISTINCT FROM (weighed.compliant, weighed.max_compliant_occupants)) THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: % weighed after inspection % and found otherwise',
            NEW.number, weighed.registration_number, weighed.id USING ERRCODE = 'restrict_violation';
    END IF;
    IF EXISTS (SELECT 1 FROM certificate c JOIN certificate_revocation r ON r.certificate_id = c.id
               WHERE c.inspection_id = weighed.id) THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: a certificate of inspection % was revoked',
            NEW.number, weighed.id USING ERRCODE = 'restrict_violation';
    END IF;
    SELECT c.id INTO current_id FROM certificate c
     WHERE c.vehicle_id = NEW.vehicle_id
       AND NOT EXISTS (SELECT 1 FROM certificate_revocation r WHERE r.certificate_id = c.id)
       AND NOT EXISTS (SELECT 1 FROM certificate s WHERE s.supersedes_id = c.id)
     ORDER BY c.id DESC LIMIT 1;
    IF NEW.supersedes_id IS DISTINCT FROM current_id THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: it must supersede the current one (id %), not %',
            NEW.number, current_id, NEW.supersedes_id USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NEW;
END $$;

CREATE FUNCTION trikecert_certificate_audited() RETURNS trigger LANGUAGE plpgsql AS $$
DECLARE
    written xid;
BEGIN
    SELECT xmin INTO written FROM certificate WHERE id = NEW.id;
    IF NOT EXISTS (
        SELECT 1 FROM audit_event e
         WHERE e.target_type = 'certificate' AND e.target_id = NEW.number AND e.xmin = written
           AND e.action = CASE WHEN NEW.kind = 'refusal' THEN 'refusal.issued' ELSE 'certificate.issued' END
           AND e.details::jsonb ->> 'kind' = NEW.kind
           AND e.details::jsonb ->> 'registration_number' = NEW.registration_number
           AND e.details::jsonb ->> 'inspection_id' = NEW.inspection_id::text) THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: no audit event of its transaction records it',
            NEW.number USING ERRCODE = 'restrict_violation';
    END IF;
    IF NOT EXISTS (SELECT 1 FROM certificate_audit a WHERE a.certificate_id = NEW.id
                   AND a.action IN ('issue', 'reissue') AND a.xmin = written)
       OR (NEW.supersedes_id IS NOT NULL AND NOT EXISTS (
           SELECT 1 FROM certificate_audit a WHERE a.certificate_id = NEW.supersedes_id
              AND a.action = 'supersede' AND a.xmin = written)) THEN
        RAISE EXCEPTION 'trikecert: certificate % refused: no certificate_audit rows written with it',
            NEW.number USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NULL;
END $$;

CREATE FUNCTION trikecert_revocation_audited() RETURNS trigger LANGUAGE plpgsql AS $$
DECLARE
    written xid;
    revoked text;
BEGIN
    SELECT xmin INTO written FROM certificate_revocation WHERE certificate_id = NEW.certificate_id;
    SELECT number INTO revoked FROM certificate WHERE id = NEW.certificate_id;
    IF NOT EXISTS (
        SELECT 1 FROM audit_event e
         WHERE e.target_type = 'certificate' AND e.target_id = revoked AND e.xmin = written
           AND e.action = 'certificate.revoked' AND e.details::jsonb ->> 'reason' = NEW.reason)
       OR NOT EXISTS (SELECT 1 FROM certificate_audit a WHERE a.certificate_id = NEW.certificate_id
                      AND a.action = 'revoke' AND a.xmin = written) THEN
        RAISE EXCEPTION 'trikecert: revocation of % refused: no audit event of this transaction records it',
            revoked USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NULL;
END $$;
"""

_PG_TRIGGERS = (
    "CREATE TRIGGER supported_inspection_plate BEFORE INSERT ON inspection "
    "FOR EACH ROW EXECUTE FUNCTION trikecert_inspection_plate()",
    "CREATE TRIGGER immutable_vehicle_registration BEFORE UPDATE OF registration_number, registration_key "
    "ON vehicle FOR EACH ROW WHEN (NEW.registration_number IS DISTINCT FROM OLD.registration_number "
    "OR NEW.registration_key IS DISTINCT FROM OLD.registration_key) "
    "EXECUTE FUNCTION trikecert_vehicle_plate_kept()",
    "CREATE TRIGGER supported_certificate BEFORE INSERT ON certificate "
    "FOR EACH ROW EXECUTE FUNCTION trikecert_certificate_supported()",
    "CREATE CONSTRAINT TRIGGER supported_certificate_audited AFTER INSERT ON certificate "
    "DEFERRABLE INITIALLY DEFERRED FOR EACH ROW EXECUTE FUNCTION trikecert_certificate_audited()",
    "CREATE CONSTRAINT TRIGGER supported_revocation_audited AFTER INSERT ON certificate_revocation "
    "DEFERRABLE INITIALLY DEFERRED FOR EACH ROW EXECUTE FUNCTION trikecert_revocation_audited()",
)
_PG_DROP = (
    "DROP TRIGGER supported_revocation_audited ON certificate_revocation",
    "DROP TRIGGER supported_certificate_audited ON certificate",
    "DROP TRIGGER supported_certificate ON certificate",
    "DROP TRIGGER immutable_vehicle_registration ON vehicle",
    "DROP TRIGGER supported_inspection_plate ON inspection",
    "DROP FUNCTION trikecert_revocation_audited()",
    "DROP FUNCTION trikecert_certificate_audited()",
    "DROP FUNCTION trikecert_certificate_supported()",
    "DROP FUNCTION trikecert_vehicle_plate_kept()",
    "DROP FUNCTION trikecert_inspection_plate()",
)


def _refuse(condition: str, message: str) -> str:
    """One check of a SQLite trigger body (the message a literal, as RAISE wants)."""
    return f"SELECT RAISE(ABORT, 'trikecert: {message}') WHERE {condition};"


_WEIGHED = "(SELECT {column} FROM inspection WHERE id = NEW.inspection_id)"
_CASES = "FROM loading_case WHERE inspection_id = NEW.inspection_id"
_FIRST_FAILING = f"(SELECT min(occupants) {_CASES} AND occupants >= 1 AND NOT compliant)"
_SQLITE_CERTIFICATE = " ".join(
    [
        "CREATE TRIGGER supported_certificate BEFORE INSERT ON certificate BEGIN",
        _refuse(
            "(NEW.kind = 'compliant') IS NOT NEW.compliant",
            "certificate refused: its kind does not match its verdict",
        ),
        _refuse(
            "NOT EXISTS (SELECT 1 FROM inspection WHERE id = NEW.inspection_id)",
            "certificate refused: its inspection is not on record",
        ),
        _refuse(
            f"{_WEIGHED.format(column='vehicle_id')} IS NOT NEW.vehicle_id "
            f"OR {_WEIGHED.format(column='registration_number')} IS NOT NEW.registration_number",
            "certificate refused: its vehicle or registration is not the one its inspection weighed",
        ),
        _refuse(
            f"NOT EXISTS (SELECT 1 {_CASES}) "
            f"OR NEW.compliant IS NOT (SELECT min(compliant = 1) {_CASES}) "
            f"OR {_WEIGHED.format(column='compliant')} IS NOT NEW.compliant "
            f"OR NEW.max_compliant_occupants IS NOT (SELECT coalesce(max(occupants), 0) {_CASES} "
            f"AND occupants >= 1 AND ({_FIRST_FAILING} IS NULL OR occupants < {_FIRST_FAILING})) "
            f"OR {_WEIGHED.format(column='max_compliant_occupants')} IS NOT NEW.max_compliant_occupants",
            "certificate refused: its verdict or occupancy differs from the loading cases of its inspection",
        ),
        _refuse(
            "json_extract(NEW.facts, '$.compliant') IS NOT NEW.compliant "
            "OR json_extract(NEW.facts, '$.max_compliant_occupants') IS NOT NEW.max_compliant_occupants "
            "OR json_extract(NEW.facts, '$.vehicle.registration_number') IS NOT NEW.registration_number "
            "OR json_extract(NEW.facts, '$.inspection.id') IS NOT NEW.inspection_id "
            "OR json_array_length(NEW.facts, '$.cases') IS NOT "
            "(SELECT count(*) FROM loading_case WHERE inspection_id = NEW.inspection_id) "
            "OR EXISTS (SELECT 1 FROM json_each(NEW.facts, '$.cases') printed WHERE NOT EXISTS "
            "(SELECT 1 FROM loading_case stored WHERE stored.inspection_id = NEW.inspection_id "
            "AND stored.occupants = json_extract(printed.value, '$.occupants') "
            "AND stored.compliant = json_extract(printed.value, '$.compliant')))",
            "certificate refused: the facts it prints are not those of its inspection",
        ),
        _refuse(
            "EXISTS (SELECT 1 FROM inspection weighed JOIN inspection later "
            "ON later.vehicle_id = weighed.vehicle_id AND (later.created_at, later.id) > "
            "(weighed.created_at, weighed.id) AND (later.compliant IS NOT weighed.compliant "
            "OR later.max_compliant_occupants IS NOT weighed.max_compliant_occupants) "
            "WHERE weighed.id = NEW.inspection_id)",
            "certificate refused: the vehicle was weighed after its inspection and found otherwise",
        ),
        _refuse(
            "EXISTS (SELECT 1 FROM certificate c JOIN certificate_revocation r ON r.certificate_id = c.id "
            "WHERE c.inspection_id = NEW.inspection_id)",
            "certificate refused: a certificate of its inspection was revoked",
        ),
        _refuse(
            "NEW.supersedes_id IS NOT (SELECT c.id FROM certificate c WHERE c.vehicle_id = NEW.vehicle_id "
            "AND NOT EXISTS (SELECT 1 FROM certificate_revocation r WHERE r.certificate_id = c.id) "
            "AND NOT EXISTS (SELECT 1 FROM certificate s WHERE s.supersedes_id = c.id) "
            "ORDER BY c.id DESC LIMIT 1)",
            "certificate refused: it must supersede the current certificate of the vehicle",
        ),
        _refuse(
            "NOT EXISTS (SELECT 1 FROM audit_event e WHERE e.target_type = 'certificate' "
            "AND e.target_id = NEW.number AND e.action = CASE WHEN NEW.kind = 'refusal' "
            "THEN 'refusal.issued' ELSE 'certificate.issued' END "
            "AND json_extract(e.details, '$.kind') = NEW.kind "
            "AND json_extract(e.details, '$.registration_number') = NEW.registration_number "
            "AND json_extract(e.details, '$.inspection_id') = NEW.inspection_id)",
            "certificate refused: no audit event records its issue",
        ),
        "END",
    ]
)
_SQLITE_TRIGGERS = (
    " ".join(
        [
            "CREATE TRIGGER supported_inspection_plate BEFORE INSERT ON inspection BEGIN",
            _refuse(
                "NEW.registration_number IS NOT "
                "(SELECT registration_number FROM vehicle WHERE id = NEW.vehicle_id)",
                "inspection refused: its registration is not that of its vehicle",
            ),
            "END",
        ]
    ),
    "CREATE TRIGGER immutable_vehicle_registration BEFORE UPDATE OF registration_number, registration_key "
    "ON vehicle WHEN NEW.registration_number IS NOT OLD.registration_number "
    "OR NEW.registration_key IS NOT OLD.registration_key BEGIN "
    "SELECT RAISE(ABORT, 'trikecert: a registration cannot be changed in place: its inspections and "
    "certificates were weighed under it'); END",
    _SQLITE_CERTIFICATE,
    " ".join(
        [
            "CREATE TRIGGER supported_revocation BEFORE INSERT ON certificate_revocation BEGIN",
            _refuse(
                "NOT EXISTS (SELECT 1 FROM audit_event e JOIN certificate c ON c.number = e.target_id "
                "WHERE c.id = NEW.certificate_id AND e.target_type = 'certificate' "
                "AND e.action = 'certificate.revoked' AND json_extract(e.details, '$.reason') = NEW.reason)",
                "revocation refused: no audit event records it",
            ),
            "END",
        ]
    ),
)
_SQLITE_DROP = (
    "DROP TRIGGER supported_revocation",
    "DROP TRIGGER supported_certificate",
    "DROP TRIGGER immutable_vehicle_registration",
    "DROP TRIGGER supported_inspection_plate",
)


def _sqlite_backfill(connection: sa.Connection) -> None:
    """Fill the new column past the inspection table's append-only triggers, then put them back."""
    triggers = connection.execute(
        sa.text("SELECT name, sql FROM sqlite_master WHERE type = 'trigger' AND tbl_name = 'inspection'")
    ).all()
    for name, _sql in triggers:
        connection.execute(sa.text(f'DROP TRIGGER "{name}"'))
    connection.execute(sa.text(_BACKFILL))
    for _name, sql in triggers:
        connection.execute(sa.text(sql))


def upgrade() -> None:
    """Apply this revision."""
    connection = op.get_bind()
    if connection.dialect.name == "postgresql":
        op.add_column("inspection", sa.Column("registration_number", sa.String(length=32), nullable=True))
        op.execute("ALTER TABLE inspection DISABLE TRIGGER immutable_inspection")
        op.execute(_BACKFILL)
        op.execute("ALTER TABLE inspection ENABLE TRIGGER immutable_inspection")
        op.alter_column("inspection", "registration_number", nullable=False)
        op.execute(_PG_FUNCTIONS)
        for statement in _PG_TRIGGERS:
            op.execute(statement)
        return
    # SQLite: NOT NULL needs a default to be added without rebuilding the table (which would drop its
    # triggers); every stored row gets its plate at once, and the insert trigger refuses a wrong one.
    op.execute("ALTER TABLE inspection ADD COLUMN registration_number VARCHAR(32) NOT NULL DEFAULT ''")
    _sqlite_backfill(connection)
    for statement in _SQLITE_TRIGGERS:
        op.execute(statement)


def downgrade() -> None:
    """Revert this revision."""
    if op.get_bind().dialect.name == "postgresql":
        for statement in _PG_DROP:
            op.execute(statement)
        op.drop_column("inspection", "registration_number")
        return
    for statement in _SQLITE_DROP:
        op.execute(statement)
    op.execute("ALTER TABLE inspection DROP COLUMN registration_number")
