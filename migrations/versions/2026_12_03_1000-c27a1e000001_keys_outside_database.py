"""the signing key leaves the database: private_pem dropped, keys held in a file or a PKCS#11 token

Until this revision the service made its signing key in the database (`signing_key.private_pem`),
where the app's own role could read it and sign anything. From here the database keeps only public
keys and metadata; the private key is held in a key file (TRIKECERT_SIGNING_KEY_FILE, by default
trikecert-signing-key.pem beside a SQLite database file) or on a PKCS#11 token.

Moving out happens here, once, so that no upgrade needs a step of its own: the active key the
database held is written to the key file the settings name (0600), unless that file already holds a
key or the key is given another way (TRIKECERT_SIGNING_KEY, a PKCS#11 token); then the database's
keys are retired, and the key held outside signs from now on. Every other private key in the
database (retired keys) is destroyed with the column. What was done is printed. When the file cannot
be written the migration stops with the reason, and nothing is changed.

Downgrading brings the column back empty (private keys never return to the database) and keeps the
wider list of sources, since keys recorded from a file or a token stay on record.

Revision ID: c27a1e000001
Revises: a9c3e5f7b201
Create Date: 2026-12-03 10:00:00
"""

from collections.abc import Sequence

import sqlalchemy as sa
from alembic import op

revision: str = "c27a1e000001"
down_revision: str | None = "a9c3e5f7b201"
branch_labels: str | Sequence[str] | None = None
depends_on: str | Sequence[str] | None = None

NEW_SOURCES = "source IN ('database', 'configuration', 'file', 'pkcs11')"


def _key_function(with_private: bool) -> str:
    private = "       OR NEW.private_pem IS DISTINCT FROM OLD.private_pem\n" if with_private else ""
    return f"""
CREATE OR REPLACE FUNCTION trikecert_signing_key_retire_only() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
    IF TG_OP = 'INSERT' THEN
        IF NEW.active AND NEW.retired_at IS NOT NULL THEN
            RAISE EXCEPTION 'trikecert: a signing key cannot be stored both active and retired'
                USING ERRCODE = 'restrict_violation';
        END IF;
        RETURN NEW;
    END IF;
    IF TG_OP = 'DELETE'
       OR NEW.id IS DISTINCT FROM OLD.id
       OR NEW.kid IS DISTINCT FROM OLD.kid
       OR NEW.public_jwk::text IS DISTINCT FROM OLD.public_jwk::text
{private}       OR NEW.source IS DISTINCT FROM OLD.source
       OR NEW.created_at IS DISTINCT FROM OLD.created_at THEN
        RAISE EXCEPTION 'trikecert: % of signing key refused: a key is kept for good and can only be retired',
            TG_OP USING ERRCODE = 'restrict_violation';
    END IF;
    IF NEW.active AND (NOT OLD.active OR OLD.retired_at IS NOT NULL OR NEW.retired_at IS NOT NULL)
       OR (OLD.retired_at IS NOT NULL AND NEW.retired_at IS DISTINCT FROM OLD.retired_at) THEN
        RAISE EXCEPTION 'trikecert: signing key % is retired and stays retired; rotate to a new key instead',
            OLD.kid USING ERRCODE = 'restrict_violation';
    END IF;
    RETURN NEW;
END $$;
"""


def _sqlite_triggers(facts: Sequence[str]) -> list[str]:
    return [
        f"CREATE TRIGGER immutable_signing_key_update BEFORE UPDATE OF {', '.join(facts)} ON signing_key "
        "BEGIN SELECT RAISE(ABORT, 'trikecert: a signing key can only be retired'); END",
        "CREATE TRIGGER immutable_signing_key_delete BEFORE DELETE ON signing_key "
        "BEGIN SELECT RAISE(ABORT, 'trikecert: a signing key is kept for good'); END",
        "CREATE TRIGGER immutable_signing_key_forward BEFORE UPDATE OF active, retired_at ON signing_key "
        "WHEN (NEW.active AND (NOT OLD.active OR OLD.retired_at IS NOT NULL OR NEW.retired_at IS NOT NULL)) "
        "OR (OLD.retired_at IS NOT NULL AND NEW.retired_at IS NOT OLD.retired_at) "
        "BEGIN SELECT RAISE(ABORT, 'trikecert: a retired signing key stays retired; rotate to a new key "
        "instead'); END",
        "CREATE TRIGGER immutable_signing_key_insert BEFORE INSERT ON signing_key "
        "WHEN NEW.active AND NEW.retired_at IS NOT NULL "
        "BEGIN SELECT RAISE(ABORT, 'trikecert: a signing key cannot be stored both active and retired'); END",
    ]


SQLITE_TRIGGERS = ("update", "delete", "forward", "insert")
FACTS = ("id", "kid", "public_jwk", "source", "created_at")


def _sqlite_table(with_private: bool) -> str:
    private = "\tprivate_pem TEXT, \n" if with_private else ""
    return (
        "CREATE TABLE _new_signing_key (\n\tid INTEGER NOT NULL, \n\tkid VARCHAR(32) NOT NULL, \n"
        f"\tpublic_jwk JSON NOT NULL, \n{private}\tsource VARCHAR(16) NOT NULL, \n"
        "\tactive BOOLEAN NOT NULL, \n\tcreated_at DATETIME NOT NULL, \n\tretired_at DATETIME, \n"
        "\tCONSTRAINT pk_signing_key PRIMARY KEY (id), \n"
        f"\tCONSTRAINT ck_signing_key_source CHECK ({NEW_SOURCES}), \n"
        "\tCONSTRAINT uq_signing_key_kid UNIQUE (kid)\n)"
    )


def _sqlite_rebuild(with_private: bool) -> None:
    """Rebuild the table with or without the column. The certificates refer to it, so their checks
    wait for the commit, and the rows go back in only once the new table has the old one's name:
    those inserts answer the references the drop left open (Alembic's batch copy cannot)."""
    columns = ", ".join((*FACTS, "active", "retired_at"))  # fixed names, no input
    # pysqlite opens the transaction at the first data change; the pragma lasts only inside one.
    op.execute("UPDATE alembic_version SET version_num = version_num WHERE 0")
    op.execute("PRAGMA defer_foreign_keys = ON")
    for name in SQLITE_TRIGGERS:
        op.execute(f"DROP TRIGGER IF EXISTS immutable_signing_key_{name}")
    op.execute(f"CREATE TEMPORARY TABLE held_signing_key AS SELECT {columns} FROM signing_key")  # noqa: S608
    op.execute(_sqlite_table(with_private))
    op.execute("DROP TABLE signing_key")
    op.execute("ALTER TABLE _new_signing_key RENAME TO signing_key")
    op.execute(f"INSERT INTO signing_key ({columns}) SELECT {columns} FROM held_signing_key")  # noqa: S608
    op.execute("DROP TABLE held_signing_key")
    facts = (*FACTS[:3], "private_pem", *FACTS[3:]) if with_private else FACTS
    for statement in _sqlite_triggers(facts):
        op.execute(statement)


def _say(line: str) -> None:
    print(f"trikecert migrate: {line}")  # the operator must read what happened to the key


def _move_keys_out(bind: sa.Connection) -> None:
    """Write the database's active private key to the key file, or retire it where the key is held
    another way; every other private key goes with the column."""
    from app.config import get_settings
    from app.db import utcnow
    from app.trust.keyfile import default_key_path, read_key_file, write_new_key_file
    from app.trust.signer import MemorySigner, parse_private_key

    rows = bind.execute(
        sa.text("SELECT kid, private_pem, active FROM signing_key WHERE private_pem IS NOT NULL ORDER BY id")
    ).all()
    if not rows:
        return
    settings = get_settings()
    active = [row for row in rows if row.active]
    moved: str | None = None
    if active and settings.signing_key is None and settings.pkcs11_module is None:
        newest = active[-1]
        path = default_key_path(settings, bind.engine.url.render_as_string(hide_password=False))
        key = parse_private_key(newest.private_pem, setting="signing_key.private_pem")
        if write_new_key_file(path, key) or MemorySigner(read_key_file(path), "file").kid == newest.kid:
            moved = newest.kid
            _say(f"moved the active signing key {newest.kid} out of the database into {path} (mode 0600)")
        else:
            _say(f"{path} already holds another key: it signs from now on")
    elif active:
        _say("the signing key is held by TRIKECERT_SIGNING_KEY or a PKCS#11 token: it signs from now on")
    retire = [row.kid for row in active if row.kid != moved]
    if retire:
        bind.execute(
            sa.text("UPDATE signing_key SET active = :no, retired_at = :now WHERE kid IN :kids").bindparams(
                sa.bindparam("kids", expanding=True)
            ),
            {"no": False, "now": utcnow(), "kids": retire},
        )
        _say(f"retired the database's signing key(s) {', '.join(retire)}; their public keys stay published")
    destroyed = len(rows) - (1 if moved else 0)
    if destroyed:
        _say(f"destroyed {destroyed} private key(s) kept in the database; old certificates still verify")


def upgrade() -> None:
    """Apply this revision."""
    bind = op.get_bind()
    _move_keys_out(bind)
    if bind.dialect.name == "postgresql":
        op.execute(_key_function(with_private=False))
        op.drop_column("signing_key", "private_pem")
        op.drop_constraint(op.f("ck_signing_key_source"), "signing_key", type_="check")
        op.create_check_constraint(op.f("ck_signing_key_source"), "signing_key", NEW_SOURCES)
        return
    _sqlite_rebuild(with_private=False)


def downgrade() -> None:
    """Revert this revision (the column comes back empty: private keys never return)."""
    bind = op.get_bind()
    if bind.dialect.name == "postgresql":
        op.add_column("signing_key", sa.Column("private_pem", sa.Text(), nullable=True))
        op.execute(_key_function(with_private=True))
        return
    _sqlite_rebuild(with_private=True)
