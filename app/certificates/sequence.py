"""Allocate the next certificate number of a year, gap-free and safe under concurrency.

One counter row per year, bumped by an atomic upsert (`INSERT ... ON CONFLICT DO UPDATE ...
RETURNING`) in the issuing transaction. On PostgreSQL the upsert locks the year's row until the
transaction ends; on SQLite it takes the database's write lock. Either way concurrent issuers
queue here, so the checks that follow see every certificate committed before, and a refused or
failed issue rolls its number back: numbers are consecutive with no gaps.
"""

from __future__ import annotations

from sqlalchemy.dialects.postgresql import Insert as PostgresInsert
from sqlalchemy.dialects.postgresql import insert as postgresql_insert
from sqlalchemy.dialects.sqlite import Insert as SqliteInsert
from sqlalchemy.dialects.sqlite import insert as sqlite_insert
from sqlalchemy.orm import Session

from app.certificates.models import CertificateSequence
from app.errors import Conflict
from app.trust.numbers import MAX_SEQUENCE, CertificateNumber


def allocate_number(session: Session, year: int) -> CertificateNumber:
    """The next number of `year`, reserved in the session's transaction (to commit or roll back)."""
    dialect = session.get_bind().dialect.name
    bump = {"last_value": CertificateSequence.last_value + 1}
    if dialect == "postgresql":
        pg = postgresql_insert(CertificateSequence).values(year=year, last_value=1)
        statement: PostgresInsert | SqliteInsert = pg.on_conflict_do_update(
            index_elements=[CertificateSequence.year], set_=bump
        )
    elif dialect == "sqlite":
        lite = sqlite_insert(CertificateSequence).values(year=year, last_value=1)
        statement = lite.on_conflict_do_update(index_elements=[CertificateSequence.year], set_=bump)
    else:  # pragma: no cover - only the two supported databases
        raise NotImplementedError(f"certificate numbers are not supported on {dialect}")
    value = session.execute(statement.returning(CertificateSequence.last_value)).scalar_one()
    if value > MAX_SEQUENCE:
        raise Conflict(
            f"the {year} certificate numbers are used up ({MAX_SEQUENCE})", rule="sequence_exhausted"
        )
    return CertificateNumber(year, value)
