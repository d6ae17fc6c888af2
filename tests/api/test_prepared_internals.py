"""app/prepared.py stands on SQLAlchemy internals: the compiler's `positiontup`, `bind_names` and
`binds`, `construct_params`, a bind's `required` and `effective_value`, the types' bind and result
processors, `exported_columns`, the dialect's `loaded_dbapi` and `is_disconnect`, and
`DBAPIError.instance`. None of them is public API, so an upgrade may change them silently.

This guard fails loudly, naming the SQLAlchemy version and the internal, when they change shape, and
checks that they still mean what prepared.py takes them to mean: every statement it prepared while
real submissions and keyed registrations ran is sent again through plain `Connection.execute`,
stopped just before the driver, and must reach it as the same SQL with the same parameters in the
same order; the read statements must give the same rows; a broken constraint must raise the same
error. When it fails: fix app/prepared.py for the new version, or drop the trick (issue 26: plain
Core execution, branch w-prepared).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import pytest
import sqlalchemy
from fastapi.testclient import TestClient
from sqlalchemy import Connection, Engine, event, exc, select
from sqlalchemy.sql.compiler import SQLCompiler
from sqlalchemy.sql.elements import BindParameter
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.db import utcnow
from app.idempotency import service as idempotency
from app.inspections import lookup, store
from app.prepared import Prepared, PreparedCache
from app.stations.models import Station
from app.stations.service import hash_key
from app.vehicles.service import lookup_key

INSPECTIONS = "/api/v1/inspections"
VEHICLE = {
    **STUDY_VEHICLE,
    "track_m": 1.15,
    "wheel_radius_m": 0.2,
    "seats": [
        {"role": "driver", "x_m": 0.9303, "z_m": 0.75},
        {"role": "passenger", "x_m": 1.6303, "z_m": 0.8},
    ],
}
SUBMISSION = {
    "registration_number": STUDY_VEHICLE["registration_number"],
    "readings": {**STUDY_READINGS, "front_kg": [107.9, 108, 108.1]},
    "measured_cases": [
        {"occupants": 1, "readings": {"front_kg": 146.5, "left_rear_kg": 141.4, "right_rear_kg": 143.1}}
    ],
    "load_items": [{"label": "gas cylinder", "mass_kg": 12.5, "x_m": 2.3}],
}
# Every statement prepared.py runs, with the dialects the app runs it on.
CACHES: dict[str, tuple[PreparedCache, tuple[str, ...]]] = {
    "lookup._COUNT_APART": (lookup._COUNT_APART, ("sqlite",)),
    "lookup._COUNTED_HERE": (lookup._COUNTED_HERE, ("postgresql",)),
    "lookup._NOT_COUNTED": (lookup._NOT_COUNTED, ("sqlite", "postgresql")),
    "store._DRAW_ID": (store._DRAW_ID, ("postgresql",)),
    "store._INSERT_INSPECTION": (store._INSERT_INSPECTION, ("sqlite",)),
    "store._INSERT_READING": (store._INSERT_READING, ("sqlite",)),
    "store._INSERT_CASE": (store._INSERT_CASE, ("sqlite",)),
    "store._ONE_STATEMENT": (store._ONE_STATEMENT, ("postgresql",)),
    "store._ONE_KEYED_STATEMENT": (store._ONE_KEYED_STATEMENT, ("postgresql",)),
    "idempotency._TRY_LOCK": (idempotency._TRY_LOCK, ("postgresql",)),
    "idempotency._STORED": (idempotency._STORED, ("sqlite", "postgresql")),
    "idempotency._REMEMBER": (idempotency._REMEMBER, ("sqlite", "postgresql")),
}
READS = ("lookup._NOT_COUNTED", "idempotency._STORED")  # run twice without changing anything


def internals_moved(internal: str, found: str) -> str:
    """The failure's message: which SQLAlchemy, which internal, what to do."""
    return (
        f"SQLAlchemy {sqlalchemy.__version__}: {internal} {found}. app/prepared.py relies on it; "
        "fix prepared.py for this version, or replace it with plain Core execution (issue 26)."
    )


class Sent(Exception):
    """What plain SQLAlchemy handed the driver, stopping it there."""

    def __init__(self, sql: str, parameters: Any, many: bool) -> None:
        super().__init__(sql)
        self.sql, self.parameters, self.many = sql, parameters, many


def sent_by_sqlalchemy(connection: Connection, statement: Any, parameters: Any) -> Sent:
    """The SQL and driver parameters `connection.execute(statement, parameters)` sends, unsent."""

    def stop(_c: Any, _cursor: Any, sql: str, sent: Any, _context: Any, many: bool) -> None:
        raise Sent(sql, sent, many)

    event.listen(connection, "before_cursor_execute", stop)
    try:
        with pytest.raises(Sent) as stopped:
            connection.execute(statement, parameters)
    finally:
        event.remove(connection, "before_cursor_execute", stop)
    connection.rollback()
    return stopped.value


def statement_of(prepared: Prepared) -> Any:
    """The Core statement a Prepared was compiled from."""
    return prepared._compiled.statement


def exact(value: Any) -> Any:
    """A value compared with its type and exact spelling (Decimal('2.0') is not Decimal('2.00'))."""
    if isinstance(value, Mapping):
        return {key: exact(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [type(value).__name__, *[exact(item) for item in value]]
    return (type(value).__name__, repr(value))


@pytest.fixture
def ran(api: TestClient, engine: Engine, station_key: str) -> list[tuple[str, Prepared, Any, bool]]:
    """Each prepared statement run while submissions and keyed registrations go through the API:
    its name, its Prepared, its values and whether it was an executemany."""
    names = {}
    with engine.connect() as connection:
        for name, (cache, dialects) in CACHES.items():
            if connection.dialect.name in dialects:
                names[id(cache(connection))] = name
    seen: list[tuple[str, Prepared, Any, bool]] = []
    execute, execute_many = Prepared.execute, Prepared.execute_many

    def recorded(self: Prepared, connection: Connection, values: Mapping[str, Any]) -> Any:
        seen.append((names.get(id(self), f"unlisted: {self.sql}"), self, dict(values), False))
        return execute(self, connection, values)

    def recorded_many(self: Prepared, connection: Connection, rows: Sequence[Mapping[str, Any]]) -> None:
        seen.append((names.get(id(self), f"unlisted: {self.sql}"), self, [dict(row) for row in rows], True))
        execute_many(self, connection, rows)

    Prepared.execute = recorded  # type: ignore[method-assign]
    Prepared.execute_many = recorded_many  # type: ignore[method-assign]
    try:
        assert api.post("/api/v1/vehicles", json=VEHICLE).status_code == 201
        assert api.post(INSPECTIONS, json=SUBMISSION).status_code == 201
        for _twice in range(2):  # the first stores the key and its answer, the second replays it
            keyed = api.post(INSPECTIONS, json=SUBMISSION, headers={"Idempotency-Key": "guard-1"})
            assert keyed.status_code == 201, keyed.text
        registration = {**VEHICLE, "registration_number": "KTU 417 XA"}
        for _twice in range(2):
            answered = api.post("/api/v1/vehicles", json=registration, headers={"Idempotency-Key": "guard-2"})
            assert answered.status_code == 201, answered.text
        with engine.connect() as connection:  # the look-up with the rate limit off (PostgreSQL too)
            registration_key = lookup_key(SUBMISSION["registration_number"])
            found = lookup.look_up(
                connection,
                key_hash=hash_key(station_key),
                registration_key=registration_key,
                window_start=None,
                idempotency_key=None,
            )
            assert found.vehicle is not None
    finally:
        Prepared.execute, Prepared.execute_many = execute, execute_many  # type: ignore[method-assign]
    return seen


def test_every_statement_the_app_runs_on_this_database_was_seen(
    ran: list[tuple[str, Prepared, Any, bool]], engine: Engine
) -> None:
    expected = {name for name, (_cache, dialects) in CACHES.items() if engine.dialect.name in dialects}
    assert {name for name, *_ in ran} == expected, "the guard no longer covers what the app prepares"


def test_the_driver_gets_the_sql_and_parameters_plain_sqlalchemy_sends(
    ran: list[tuple[str, Prepared, Any, bool]], engine: Engine
) -> None:
    with engine.connect() as connection:
        for name, prepared, values, many in ran:
            statement = statement_of(prepared)
            sent = sent_by_sqlalchemy(connection, statement, values)
            where = f"{name} on {engine.dialect.name}"
            assert sent.sql == prepared.sql, internals_moved(
                "Compiled.string", f"is no longer the SQL Connection.execute sends ({where})"
            )
            ours = [prepared.parameters(row) for row in values] if many else prepared.parameters(values)
            order = "positiontup" if prepared._order is not None else "bind_names"
            assert exact(sent.parameters) == exact(ours), internals_moved(
                f"SQLCompiler.{order} with the binds' processors",
                f"no longer gives the parameters, their order and values Connection.execute sends ({where})",
            )


def test_the_read_statements_give_the_rows_plain_sqlalchemy_gives(
    ran: list[tuple[str, Prepared, Any, bool]], engine: Engine
) -> None:
    checked = 0
    with engine.connect() as connection:
        for name, prepared, values, _many in ran:
            if name not in READS:
                continue
            ours = prepared.execute(connection, values)
            plain = [dict(row) for row in connection.execute(statement_of(prepared), values).mappings()]
            connection.rollback()
            assert exact(ours) == exact(plain), internals_moved(
                "TypeEngine.result_processor and exported_columns",
                f"no longer give the rows Connection.execute gives ({name} on {engine.dialect.name})",
            )
            checked += bool(ours)
    assert checked >= 2, "the read statements found rows to compare (a vehicle and a stored key)"


def test_a_broken_constraint_raises_what_plain_sqlalchemy_raises(api: TestClient, engine: Engine) -> None:
    with engine.connect() as connection:
        station_id = connection.execute(select(Station.id)).scalar_one()
        prepared = idempotency._REMEMBER(connection)
    row = {
        "station_id": station_id,
        "key": "guard-duplicate",
        "operation": "guard",
        "request_hash": "0" * 64,
        "status_code": 201,
        "response_body": "{}",
        "created_at": utcnow(),
    }
    ours = _second_fails(engine, lambda c: prepared.execute(c, row))
    plain = _second_fails(engine, lambda c: c.execute(statement_of(prepared), row))
    assert (type(ours), type(ours.orig)) == (type(plain), type(plain.orig)), internals_moved(
        "DBAPIError.instance", f"wraps a driver error as {type(ours)}, Connection.execute as {type(plain)}"
    )
    assert isinstance(ours, exc.IntegrityError)


def _second_fails(engine: Engine, run: Callable[[Connection], Any]) -> exc.DBAPIError:
    """Run the insert twice in one transaction, then roll it back: the second's error."""
    with engine.connect() as connection:
        transaction = connection.begin()
        try:
            run(connection)
            with pytest.raises(exc.DBAPIError) as second:
                run(connection)
        finally:
            transaction.rollback()
    return second.value


def test_the_compiler_internals_keep_their_shape(engine: Engine) -> None:
    dialect = engine.dialect
    for name, (cache, dialects) in CACHES.items():
        if dialect.name not in dialects:
            continue
        statement = cache._build(dialect.name)
        compiled = statement.compile(dialect=dialect)
        where = f"({name} on {dialect.name})"
        assert isinstance(compiled, SQLCompiler), internals_moved(
            "ClauseElement.compile()", f"no longer gives an SQLCompiler {where}"
        )
        binds = getattr(compiled, "binds", None)
        named_binds = isinstance(binds, dict) and all(
            isinstance(key, str) and isinstance(bind, BindParameter) for key, bind in binds.items()
        )
        assert named_binds, internals_moved(
            "SQLCompiler.binds", f"is no longer a dict of name to BindParameter {where}"
        )
        assert isinstance(binds, dict)
        bind_names = getattr(compiled, "bind_names", None)
        every_bind_named = isinstance(bind_names, dict) and all(
            isinstance(bind_names.get(bind), str) for bind in binds.values()
        )
        assert every_bind_named, internals_moved(
            "SQLCompiler.bind_names", f"no longer names every bind in .binds {where}"
        )
        assert isinstance(bind_names, dict)
        positiontup = getattr(compiled, "positiontup", "missing")
        if dialect.paramstyle in ("qmark", "numeric", "format"):
            listed = isinstance(positiontup, list) and all(isinstance(n, str) for n in positiontup)
            assert listed, internals_moved(
                "SQLCompiler.positiontup", f"is not a list of bind names for a positional driver {where}"
            )
            placeholder = "?" if dialect.paramstyle == "qmark" else "%s"
            assert len(positiontup) == compiled.string.count(placeholder), internals_moved(
                "SQLCompiler.positiontup", f"does not match the SQL's placeholders {where}"
            )
        else:
            assert positiontup is None, internals_moved(
                "SQLCompiler.positiontup",
                f"is {positiontup!r}, not None, for a named-parameter driver {where}",
            )
        params = compiled.construct_params({bind.key: None for bind in binds.values()})
        by_name = isinstance(params, dict) and set(params) <= set(bind_names.values())
        assert by_name, internals_moved(
            "SQLCompiler.construct_params", f"no longer gives a dict by bind name {where}"
        )
        for bind in binds.values():
            assert isinstance(getattr(bind, "required", None), bool), internals_moved(
                "BindParameter.required", f"is not a bool {where}"
            )
            assert hasattr(bind, "effective_value"), internals_moved(
                "BindParameter.effective_value", f"is gone {where}"
            )
            processor = bind.type.dialect_impl(dialect).bind_processor(dialect)
            assert processor is None or callable(processor), internals_moved(
                "TypeEngine.bind_processor", f"gives {processor!r} {where}"
            )
        for column in getattr(statement, "exported_columns", ()):
            assert isinstance(column.name, str), internals_moved(
                "exported_columns", f"has a column without a name {where}"
            )
    assert isinstance(getattr(dialect, "loaded_dbapi", None).Error, type), internals_moved(  # type: ignore[union-attr]
        "Dialect.loaded_dbapi.Error", "is not the driver's error class"
    )
    assert callable(getattr(dialect, "is_disconnect", None)), internals_moved(
        "Dialect.is_disconnect", "is gone"
    )
    assert callable(getattr(exc.DBAPIError, "instance", None)), internals_moved(
        "DBAPIError.instance", "is gone"
    )
