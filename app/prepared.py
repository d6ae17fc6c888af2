"""A Core statement compiled once per dialect and run as the driver's SQL, for the submission's hot path.

The statement is written with SQLAlchemy Core against the mapped tables, and its parameters and
result columns go through SQLAlchemy's own type processing (JSON, UTC datetimes, SQLite's decimals),
worked out once; what is skipped is the per-execution work of `Connection.execute` (compiled-cache
lookup, execution context, result metadata), which measured as much again as the driver's own time.
It runs on the driver connection of a SQLAlchemy connection, in its transaction: the pool, the
transactions and the SQLite writer's turn stay SQLAlchemy's, and a driver error is raised as
SQLAlchemy raises it (a lost database is still recognised as an outage). Its statements do not pass
through SQLAlchemy's cursor events.

It leans on SQLAlchemy internals (the compiler's positiontup, bind_names and binds, the types'
processors): tests/api/test_prepared_internals.py fails, naming the version and the internal, when
an upgrade changes what they give.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from sqlalchemy import Connection, Dialect, exc
from sqlalchemy.sql import ClauseElement
from sqlalchemy.sql.compiler import SQLCompiler

Processor = Callable[[Any], Any] | None


class Prepared:
    """One statement compiled for one dialect, with its parameter and result-column processors."""

    def __init__(self, statement: ClauseElement, dialect: Dialect) -> None:
        compiled = statement.compile(dialect=dialect)
        assert isinstance(compiled, SQLCompiler)
        self._compiled = compiled
        self.sql = compiled.string
        self._order = compiled.positiontup  # None: named parameters
        # Each parameter the SQL names, with its processor; the statement's own literals (a constant
        # 1, say) are bound once, here.
        names = compiled.construct_params(_every_value(compiled))
        self._bind: dict[str, Processor] = {}
        self._literals: dict[str, Any] = {}
        for bind in compiled.binds.values():
            name = compiled.bind_names[bind]
            if name not in names:
                continue
            process = bind.type.dialect_impl(dialect).bind_processor(dialect)
            if bind.required:
                self._bind[name] = process
            else:
                value = bind.effective_value
                self._literals[name] = value if process is None else process(value)
        self._dialect = dialect
        self._selected = tuple(getattr(statement, "exported_columns", ()))
        self.columns = tuple(column.name for column in self._selected)
        repeated = {name for name in self.columns if self.columns.count(name) > 1}
        if repeated:  # rows are dicts by column name: one would hide the other
            raise ValueError(f"the statement selects {sorted(repeated)} more than once; label them apart")
        self._result: tuple[Processor, ...] | None = None  # from the first result's column types

    def parameters(self, values: Mapping[str, Any]) -> dict[str, Any] | tuple[Any, ...]:
        """The driver's parameters for these values (and the statement's own literals), processed."""
        processed = {
            name: values[name] if process is None else process(values[name])
            for name, process in self._bind.items()
        }
        processed.update(self._literals)
        if self._order is None:
            return processed
        return tuple(processed[name] for name in self._order)

    def execute(self, connection: Connection, values: Mapping[str, Any]) -> list[dict[str, Any]]:
        """Run it once; the rows it returns (if any) as dicts of processed column values."""
        rows, description = self._run(connection, self.parameters(values), many=False)
        if description is None:
            return []
        if self._result is None:  # the driver's type of each column decides its processor (PostgreSQL)
            self._result = tuple(
                column.type.dialect_impl(self._dialect).result_processor(self._dialect, described[1])
                for column, described in zip(self._selected, description, strict=True)
            )
        processors = self._result
        return [
            {
                name: value if process is None or value is None else process(value)
                for name, process, value in zip(self.columns, processors, row, strict=True)
            }
            for row in rows
        ]

    def execute_many(self, connection: Connection, rows: Sequence[Mapping[str, Any]]) -> None:
        """Run it once per row of values, as one executemany."""
        self._run(connection, [self.parameters(row) for row in rows], many=True)

    def _run(self, connection: Connection, parameters: Any, *, many: bool) -> tuple[list[Any], Any]:
        """Send the SQL on the connection's driver connection, in whatever transaction it is in.

        A driver error is raised as SQLAlchemy's (`DBAPIError.instance`, as `Connection.execute`
        would), and a lost connection is invalidated first, so an outage is still answered as one.
        """
        dialect = connection.dialect
        driver_connection = connection.connection.dbapi_connection
        assert driver_connection is not None
        cursor = driver_connection.cursor()
        try:
            if many:
                cursor.executemany(self.sql, parameters)
            else:
                cursor.execute(self.sql, parameters)
            description = cursor.description
            return (list(cursor.fetchall()) if description is not None else []), description
        except dialect.loaded_dbapi.Error as error:
            lost = dialect.is_disconnect(error, driver_connection, cursor)
            if lost:
                connection.invalidate(error)
            raise exc.DBAPIError.instance(
                self.sql,
                parameters,
                error,
                dialect.loaded_dbapi.Error,
                connection_invalidated=lost,
                dialect=dialect,
            ) from error
        finally:
            cursor.close()


class PreparedCache:
    """A statement's `Prepared` for each dialect it meets, made on first use (`build` is given the
    dialect's name)."""

    def __init__(self, build: Callable[[str], ClauseElement]) -> None:
        self._build = build
        self._by_dialect: dict[str, Prepared] = {}

    def __call__(self, connection: Connection) -> Prepared:
        """The statement prepared for this connection's dialect."""
        name = connection.dialect.name
        if name not in self._by_dialect:
            self._by_dialect[name] = Prepared(self._build(name), connection.dialect)
        return self._by_dialect[name]


def _every_value(compiled: SQLCompiler) -> dict[str, Any]:
    """A placeholder value for every parameter the statement takes, to list the names it binds."""
    return {bind.key: None for bind in compiled.binds.values()}
