"""Write a decided inspection for good: its row, every raw reading and every loading case, at once.

PostgreSQL takes the three INSERTs as one statement (data-modifying CTEs), so a submission's write
is one round trip, and in autocommit a transaction of its own:

    WITH inspection AS (INSERT INTO inspection (...) VALUES (...) RETURNING id),
         reading AS (INSERT INTO reading (...) SELECT inspection.id, r.* FROM inspection,
                     json_to_recordset(:readings) AS r(case_occupants INTEGER, ...)),
         loading_case AS (INSERT INTO loading_case (...) SELECT inspection.id, c.* FROM inspection,
                          json_to_recordset(:cases) AS c(occupants INTEGER, ...))
    SELECT id FROM inspection

The rows go as two JSON documents, decimals as strings (exact: read as NUMERIC): one text parameter
each is cheap to send, where an array per column costs the driver a conversion per value.

SQLite has no data-modifying CTEs, and no round trip to save: three INSERTs (the readings and the
cases each one executemany) in the caller's transaction.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from typing import Any

from sqlalchemy import JSON, Connection, Table, Text, bindparam, cast, column, func, insert, select, true

from app.idempotency.service import KEYS_TABLE, Claim, KeyInFlight, lock_id, remember
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.inspections.record import INSPECTION_COLUMNS, CaseRow, InspectionRecord, ReadingRow
from app.prepared import PreparedCache

_INSPECTION: Table = Inspection.__table__  # type: ignore[assignment]
_READING: Table = Reading.__table__  # type: ignore[assignment]
_CASE: Table = LoadingCaseRow.__table__  # type: ignore[assignment]
_READING_FIELDS = tuple(f.name for f in fields(ReadingRow))
_CASE_FIELDS = tuple(f.name for f in fields(CaseRow))


@dataclass(frozen=True)
class KeptAnswer:
    """An Idempotency-Key to store with the inspection, and how to make its answer from the record."""

    claim: Claim
    status_code: int
    answer: Callable[[InspectionRecord], bytes]


def store_record(connection: Connection, record: InspectionRecord, *, keep: KeptAnswer | None = None) -> int:
    """Insert the inspection, its readings and its loading cases (and the answer kept under an
    Idempotency-Key) in the connection's transaction; the inspection's id.

    PostgreSQL writes it all in one statement (a connection in autocommit makes it a transaction of
    its own). With a key it inserts `record.id`, drawn just before (`draw_inspection_id`), so the
    kept answer is complete beforehand, and it first takes the key's lock: KeyInFlight (and nothing
    stored) when another request holds it. A key already stored raises IntegrityError, and nothing
    is stored. SQLite learns the id from the insert.
    """
    columns = record.columns()
    if connection.dialect.name == "postgresql":
        rows = {"readings": _json_rows(record.readings), "cases": _json_rows(record.cases)}
        if keep is None:
            return int(_ONE_STATEMENT(connection).execute(connection, {**columns, **rows})[0]["id"])
        kept = _kept(keep, record)
        [row] = _ONE_KEYED_STATEMENT(connection).execute(
            connection, {**columns, **rows, **kept, "id": record.id}
        )
        if not row["held"]:
            raise KeyInFlight()
        return record.id
    inspection_id = int(_INSERT_INSPECTION(connection).execute(connection, columns)[0]["id"])
    _INSERT_READING(connection).execute_many(
        connection, [{**vars(row), "inspection_id": inspection_id} for row in record.readings]
    )
    _INSERT_CASE(connection).execute_many(
        connection, [{**vars(row), "inspection_id": inspection_id} for row in record.cases]
    )
    if keep is not None:
        kept = _kept(keep, replace(record, id=inspection_id))
        remember(
            connection, keep.claim, status_code=keep.status_code, body=kept["key_response_body"].encode()
        )
    return inspection_id


def draw_inspection_id(connection: Connection) -> int:
    """PostgreSQL: the next inspection id, for a keyed `store_record` (SQLite: 0, its insert makes one)."""
    if connection.dialect.name != "postgresql":
        return 0
    return int(_DRAW_ID(connection).execute(connection, {})[0]["id"])


_DRAW_ID = PreparedCache(
    lambda _dialect: select(func.nextval(func.pg_get_serial_sequence("inspection", "id")).label("id"))
)


def _kept(keep: KeptAnswer, record: InspectionRecord) -> dict[str, Any]:
    """The key's row as the keyed statement's parameters (its station and time are the record's)."""
    claim = keep.claim
    return {
        "lock": lock_id(claim),
        "key_key": claim.key,
        "key_operation": claim.operation,
        "key_request_hash": claim.request_hash,
        "key_status_code": keep.status_code,
        "key_response_body": keep.answer(record).decode(),
    }


def _values(table: Table, names: tuple[str, ...]) -> dict[str, Any]:
    """VALUES (:a, :b, ...) for these columns, each parameter typed as its column."""
    return {name: bindparam(name, type_=table.c[name].type) for name in names}


_INSERT_INSPECTION = PreparedCache(
    lambda _dialect: (
        insert(_INSPECTION).values(_values(_INSPECTION, INSPECTION_COLUMNS)).returning(_INSPECTION.c.id)
    )
)
_INSERT_READING = PreparedCache(
    lambda _dialect: insert(_READING).values(_values(_READING, ("inspection_id", *_READING_FIELDS)))
)
_INSERT_CASE = PreparedCache(
    lambda _dialect: insert(_CASE).values(_values(_CASE, ("inspection_id", *_CASE_FIELDS)))
)


def _json_rows(rows: tuple[ReadingRow, ...] | tuple[CaseRow, ...]) -> str:
    """Rows as a JSON array of objects, decimals as strings (exact: PostgreSQL reads them as NUMERIC)."""
    return json.dumps([vars(row) for row in rows], default=str, separators=(",", ":"))


def _rows_of(table: Table, parameter: str, names: tuple[str, ...]) -> Any:
    """json_to_recordset(:parameter) AS parameter_rows(a TYPE, b TYPE, ...), typed as the table's columns."""
    document = cast(bindparam(parameter, type_=Text), JSON)
    columns = [column(name, table.c[name].type) for name in names]
    return (
        func.json_to_recordset(document)
        .table_valued(*columns)
        .render_derived(name=f"{parameter}_rows", with_types=True)
    )


def _one_statement(*, keyed: bool) -> Any:
    """PostgreSQL: the inspection, its readings and its cases in one statement, returning its id;
    keyed, the inspection's id is given, all of it waits on the key's lock being held, the key's
    row is written too, and the statement returns whether the lock was held."""
    names = ("id", *INSPECTION_COLUMNS) if keyed else INSPECTION_COLUMNS
    values = select(*_values(_INSPECTION, names).values())
    claim = select(func.pg_try_advisory_xact_lock(bindparam("lock")).label("held")).cte("claim")
    if keyed:
        values = values.select_from(claim).where(claim.c.held)
    inspection = (
        insert(_INSPECTION).from_select(list(names), values).returning(_INSPECTION.c.id).cte("new_inspection")
    )
    readings = _rows_of(_READING, "readings", _READING_FIELDS)
    cases = _rows_of(_CASE, "cases", _CASE_FIELDS)
    insert_readings = insert(_READING).from_select(
        ["inspection_id", *_READING_FIELDS],
        select(inspection.c.id, *[readings.c[name] for name in _READING_FIELDS]).join_from(
            inspection, readings, true()
        ),
    )
    insert_cases = insert(_CASE).from_select(
        ["inspection_id", *_CASE_FIELDS],
        select(inspection.c.id, *[cases.c[name] for name in _CASE_FIELDS]).join_from(
            inspection, cases, true()
        ),
    )
    ctes = [insert_readings.cte("new_readings"), insert_cases.cte("new_cases")]
    if not keyed:
        return select(inspection.c.id).add_cte(*ctes)
    key_columns = {
        "station_id": bindparam("station_id", type_=KEYS_TABLE.c.station_id.type),
        "created_at": bindparam("created_at", type_=KEYS_TABLE.c.created_at.type),
        **{
            name: bindparam(f"key_{name}", type_=KEYS_TABLE.c[name].type)
            for name in ("key", "operation", "request_hash", "status_code", "response_body")
        },
    }
    insert_key = insert(KEYS_TABLE).from_select(
        list(key_columns), select(*key_columns.values()).select_from(inspection)
    )
    return select(claim.c.held).add_cte(*ctes, insert_key.cte("new_key"))


_ONE_STATEMENT = PreparedCache(lambda _dialect: _one_statement(keyed=False))
_ONE_KEYED_STATEMENT = PreparedCache(lambda _dialect: _one_statement(keyed=True))
