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
from dataclasses import fields
from typing import Any

from sqlalchemy import JSON, Connection, Table, Text, bindparam, cast, column, func, insert, select, true

from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.inspections.record import INSPECTION_COLUMNS, CaseRow, InspectionRecord, ReadingRow
from app.prepared import PreparedCache

_INSPECTION: Table = Inspection.__table__  # type: ignore[assignment]
_READING: Table = Reading.__table__  # type: ignore[assignment]
_CASE: Table = LoadingCaseRow.__table__  # type: ignore[assignment]
_READING_FIELDS = tuple(f.name for f in fields(ReadingRow))
_CASE_FIELDS = tuple(f.name for f in fields(CaseRow))


def store_record(connection: Connection, record: InspectionRecord) -> int:
    """Insert the inspection, its readings and its loading cases; the new inspection's id.

    In the connection's transaction if it has one; a PostgreSQL connection in autocommit makes it
    one transaction of its own (all three tables or none).
    """
    columns = record.columns()
    if connection.dialect.name == "postgresql":
        rows = {"readings": _json_rows(record.readings), "cases": _json_rows(record.cases)}
        return int(_ONE_STATEMENT(connection).execute(connection, {**columns, **rows})[0]["id"])
    inspection_id = int(_INSERT_INSPECTION(connection).execute(connection, columns)[0]["id"])
    _INSERT_READING(connection).execute_many(
        connection, [{**vars(row), "inspection_id": inspection_id} for row in record.readings]
    )
    _INSERT_CASE(connection).execute_many(
        connection, [{**vars(row), "inspection_id": inspection_id} for row in record.cases]
    )
    return inspection_id


def _values(table: Table, names: tuple[str, ...]) -> dict[str, Any]:
    """VALUES (:a, :b, ...) for these columns, each parameter typed as its column."""
    return {name: bindparam(name, type_=table.c[name].type) for name in names}


_INSERT_INSPECTION = PreparedCache(
    lambda: insert(_INSPECTION).values(_values(_INSPECTION, INSPECTION_COLUMNS)).returning(_INSPECTION.c.id)
)
_INSERT_READING = PreparedCache(
    lambda: insert(_READING).values(_values(_READING, ("inspection_id", *_READING_FIELDS)))
)
_INSERT_CASE = PreparedCache(lambda: insert(_CASE).values(_values(_CASE, ("inspection_id", *_CASE_FIELDS))))


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


def _one_statement() -> Any:
    """PostgreSQL: the inspection, its readings and its cases in one statement."""
    inspection = (
        insert(_INSPECTION)
        .values(_values(_INSPECTION, INSPECTION_COLUMNS))
        .returning(_INSPECTION.c.id)
        .cte("new_inspection")
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
    return select(inspection.c.id).add_cte(insert_readings.cte("new_readings"), insert_cases.cte("new_cases"))


_ONE_STATEMENT = PreparedCache(_one_statement)
