"""The access log's lines written while a block of a test runs, as their fields."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any


class _Lines(logging.Handler):
    def __init__(self, lines: list[dict[str, Any]]) -> None:
        super().__init__()
        self.lines = lines

    def emit(self, record: logging.LogRecord) -> None:
        self.lines.append(getattr(record, "fields", {}))


@contextmanager
def access_lines() -> Iterator[list[dict[str, Any]]]:
    """The fields of each access line logged inside the block, in order."""
    lines: list[dict[str, Any]] = []
    handler = _Lines(lines)
    access = logging.getLogger("trikecert.access")
    access.addHandler(handler)
    try:
        yield lines
    finally:
        access.removeHandler(handler)
