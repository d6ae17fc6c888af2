"""Rows per table of the run's database, read in one statement (tests that assert "nothing was stored"
read them before and after every refused request, hundreds of times a test)."""

from __future__ import annotations

from collections.abc import Collection
from functools import cache
from typing import Any

from sqlalchemy import Engine, Select, func, select

from app.db import Base


def rows_per_table(engine: Engine, *, leave_out: Collection[str] = ()) -> dict[str, int]:
    """Rows in each table of the app (but those named in `leave_out`), as one consistent reading."""
    names, statement = _counting(frozenset(leave_out))
    with engine.connect() as connection:
        return dict(zip(names, connection.execute(statement).one(), strict=True))


@cache
def _counting(leave_out: frozenset[str]) -> tuple[list[str], Select[Any]]:
    """The tables counted and the statement counting all of them at once."""
    tables = [table for table in Base.metadata.sorted_tables if table.name not in leave_out]
    statement = select(*(select(func.count()).select_from(table).scalar_subquery() for table in tables))
    return [table.name for table in tables], statement
