"""The on-disk queue (a small SQLite file): every weighing is stored, with its Idempotency-Key, before
anything is sent, and stays until the service has answered it (delivered or rejected)."""

from __future__ import annotations

import json
import sqlite3
import uuid
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from app.station_client.files import Weighing

SCHEMA = """
CREATE TABLE IF NOT EXISTS weighing (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    idempotency_key TEXT NOT NULL UNIQUE,
    source TEXT UNIQUE,
    registration_number TEXT NOT NULL,
    body TEXT NOT NULL,
    state TEXT NOT NULL DEFAULT 'pending' CHECK (state IN ('pending', 'delivered', 'rejected')),
    attempts INTEGER NOT NULL DEFAULT 0,
    inspection_id INTEGER,
    http_status INTEGER,
    message TEXT,
    queued_at TEXT NOT NULL,
    answered_at TEXT
)
"""


def _now() -> str:
    return datetime.now(UTC).isoformat(timespec="seconds")


@dataclass(frozen=True)
class Queued:
    """A weighing in the queue and what has become of it."""

    id: int
    idempotency_key: str
    source: str | None
    registration_number: str
    body: str
    state: str
    attempts: int
    inspection_id: int | None
    http_status: int | None
    message: str | None
    queued_at: str
    answered_at: str | None


class Outbox:
    """The queue file; every change is committed (and synced to disk) before the call returns."""

    def __init__(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.connection = sqlite3.connect(path, isolation_level=None, timeout=30)
        self.connection.row_factory = sqlite3.Row
        self.connection.execute("PRAGMA journal_mode=WAL")
        self.connection.execute("PRAGMA synchronous=FULL")
        self.connection.execute(SCHEMA)

    def close(self) -> None:
        """Close the file."""
        self.connection.close()

    def _write(self, sql: str, parameters: Sequence[Any]) -> None:
        self.connection.execute(sql, parameters)

    def enqueue(self, weighings: Sequence[Weighing]) -> tuple[list[int], int]:
        """Queue the weighings in one transaction, each with a new key: the new ids, and how many were
        queued already (the same row of the same file)."""
        queued: list[int] = []
        self.connection.execute("BEGIN IMMEDIATE")
        try:
            for weighing in weighings:
                if (
                    weighing.source is not None
                    and self.connection.execute(
                        "SELECT 1 FROM weighing WHERE source = ?", (weighing.source,)
                    ).fetchone()
                ):
                    continue
                cursor = self.connection.execute(
                    "INSERT INTO weighing (idempotency_key, source, registration_number, body, queued_at) "
                    "VALUES (?, ?, ?, ?, ?)",
                    (
                        str(uuid.uuid4()),
                        weighing.source,
                        weighing.registration_number,
                        json.dumps(weighing.body, separators=(",", ":")),
                        _now(),
                    ),
                )
                queued.append(int(cursor.lastrowid or 0))
            self.connection.execute("COMMIT")
        except BaseException:
            self.connection.execute("ROLLBACK")
            raise
        return queued, len(weighings) - len(queued)

    def _select(self, where: str = "1 = 1", parameters: Sequence[Any] = ()) -> list[Queued]:
        rows = self.connection.execute(f"SELECT * FROM weighing WHERE {where} ORDER BY id", parameters)  # noqa: S608
        return [Queued(**dict(row)) for row in rows]

    def pending(self) -> list[Queued]:
        """The weighings the service has not answered yet, oldest first."""
        return self._select("state = 'pending'")

    def every(self) -> list[Queued]:
        """Every weighing in the queue, oldest first."""
        return self._select()

    def get(self, weighing_id: int) -> Queued:
        """One weighing by its queue id."""
        return self._select("id = ?", (weighing_id,))[0]

    def note_attempt(self, weighing_id: int, message: str) -> None:
        """Count a try that got no final answer, and why."""
        self._write(
            "UPDATE weighing SET attempts = attempts + 1, message = ? WHERE id = ?", (message, weighing_id)
        )

    def mark_delivered(self, weighing_id: int, *, inspection_id: int | None, http_status: int) -> None:
        """The service stored it (or had stored it: a replayed answer) as this inspection."""
        self._write(
            "UPDATE weighing SET state = 'delivered', attempts = attempts + 1, inspection_id = ?, "
            "http_status = ?, message = NULL, answered_at = ? WHERE id = ?",
            (inspection_id, http_status, _now(), weighing_id),
        )

    def mark_rejected(self, weighing_id: int, *, http_status: int, message: str) -> None:
        """The service refused it for good, with this message; it is not sent again."""
        self._write(
            "UPDATE weighing SET state = 'rejected', attempts = attempts + 1, http_status = ?, message = ?, "
            "answered_at = ? WHERE id = ?",
            (http_status, message, _now(), weighing_id),
        )

    def find(self, weighing_id: int) -> Queued | None:
        """One weighing by its queue id, or None when the queue has no such weighing."""
        found = self._select("id = ?", (weighing_id,))
        return found[0] if found else None

    def requeue(self, weighing_id: int) -> bool:
        """Put a rejected weighing back in the queue to be sent again, under the same Idempotency-Key
        (so a weighing the service did store once is answered with that inspection, never stored twice);
        False when it was not rejected."""
        cursor = self.connection.execute(
            "UPDATE weighing SET state = 'pending', answered_at = NULL WHERE id = ? AND state = 'rejected'",
            (weighing_id,),
        )
        return cursor.rowcount == 1
