"""Record ids from outside (paths, queries, the command line), bounded in this one place.

Ids are INTEGER columns: 32 bits on PostgreSQL, 64 on SQLite. A larger number cannot name a stored
record on any backend, and handed to the database it would overflow (a 500) instead of being refused.
Doors refuse an out-of-range id before any query: the API with a 422 naming the parameter (its schema
states the bounds: app/api/ids.py), the pages with their 404, the command line with a usage error.
Nothing here imports the web framework: every command of `trikecert` reads ids through this module.
"""

from __future__ import annotations

import argparse

MAX_ID = 2**31 - 1
_MAX_DIGITS = len(str(MAX_ID))


def parse_id(text: str) -> int | None:
    """The id written in `text` (digits, 1 to MAX_ID), or None when it cannot name a record."""
    text = text.strip()
    if not text.isascii() or not text.isdigit() or len(text) > _MAX_DIGITS:
        return None
    number = int(text)
    return number if 1 <= number <= MAX_ID else None


def cli_id(text: str) -> int:
    """An argparse `type`: the id, or a usage error naming the range."""
    number = parse_id(text)
    if number is None:
        raise argparse.ArgumentTypeError(f"{text!r} is not an id (a whole number from 1 to {MAX_ID})")
    return number
