"""Done when: the station client delivers every queued weighing exactly once across a service outage
and a client restart. Real processes: `trikecert serve`, and `python -m app.station_client` (the
`trikecert-station` command) as a station PC runs it; the service is killed mid-queue, the client
is killed while it retries, both are started again, and the database holds each weighing once."""

from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Callable
from pathlib import Path
from typing import IO

from sqlalchemy import Engine, select
from sqlalchemy.orm import Session
from station_server import Server, count_inspections, seed_station, seed_study_vehicle

from app.inspections.models import Inspection

WEIGHINGS = 6
CLIENT = [sys.executable, "-m", "app.station_client"]
UNREACHABLE = "the service could not be reached"
FAST_RETRIES = ["--backoff-base", "0.05", "--backoff-cap", "0.3", "--give-up-after", "20", "--timeout", "5"]


def wait_for(condition: Callable[[], bool], what: str, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting until {what}")
        time.sleep(0.01)


class Output:
    """A running process's stdout and stderr, read as they come (a pipe left unread would block it)."""

    def __init__(self, process: subprocess.Popen[str]) -> None:
        self.lock = threading.Lock()
        self.out: list[str] = []
        self.err: list[str] = []
        assert process.stdout is not None
        assert process.stderr is not None
        self.readers = [
            threading.Thread(target=self._read, args=(stream, lines), daemon=True)
            for stream, lines in ((process.stdout, self.out), (process.stderr, self.err))
        ]
        for reader in self.readers:
            reader.start()

    def _read(self, stream: IO[str], lines: list[str]) -> None:
        for line in stream:
            with self.lock:
                lines.append(line)

    def text(self) -> str:
        """Stdout so far."""
        with self.lock:
            return "".join(self.out)

    def finish(self) -> tuple[str, str]:
        """Stdout and stderr, once the process has ended."""
        for reader in self.readers:
            reader.join(timeout=10)
        return "".join(self.out), "".join(self.err)


def queue_rows(queue: Path) -> list[tuple[int, str, str, int | None, int]]:
    with sqlite3.connect(queue) as connection:
        rows = connection.execute(
            "SELECT id, idempotency_key, state, inspection_id, attempts FROM weighing ORDER BY id"
        ).fetchall()
    return [tuple(row) for row in rows]


def weighings_csv(path: Path) -> Path:
    lines = ["registration_number,front_kg,left_rear_kg,right_rear_kg,overall_kg"]
    lines += [f"BDG 252 QH,{108 + i * 0.5},115,135,{359 + i * 0.5}" for i in range(WEIGHINGS)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_every_queued_weighing_is_stored_exactly_once_across_an_outage_and_a_client_restart(
    database_url: str, session: Session, engine: Engine, tmp_path: Path
) -> None:
    _station_id, key = seed_station(session, "Roadside weighbridge")
    seed_study_vehicle(session)
    # One request a second: the client meets 429 and Retry-After, and the queue drains slowly enough
    # to stop the service part-way through it (4 more would take 3 windows; the test polls every 10 ms).
    server = Server(
        database_url,
        env={"TRIKECERT_STATION_RATE_LIMIT": "1", "TRIKECERT_STATION_RATE_WINDOW_SECONDS": "1"},
    )
    queue = tmp_path / "station" / "queue.db"
    env = dict(
        os.environ,
        TRIKECERT_STATION_KEY=key,
        TRIKECERT_STATION_QUEUE=str(queue),
        TRIKECERT_STATION_URL=server.url,
        PYTHONUNBUFFERED="1",
    )
    queued = subprocess.run(
        [*CLIENT, "queue", str(weighings_csv(tmp_path / "today.csv"))],
        env=env,
        capture_output=True,
        text=True,
    )
    assert queued.returncode == 0, queued.stderr
    assert f"queued {WEIGHINGS} weighing(s)" in queued.stdout
    server.start()
    try:
        # The first weighing was sent once before, and its answer lost on the way back.
        first_key, first_body = _first_queued(queue)
        first_id = _post(server.url, key, first_key, first_body)
        assert count_inspections(session) == 1

        client = subprocess.Popen(
            [*CLIENT, "send", *FAST_RETRIES],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        output = Output(client)
        wait_for(lambda: count_inspections(session) >= 2, "the client has delivered some weighings")
        server.kill()  # the service dies mid-queue
        stored_before_outage = count_inspections(session)
        assert stored_before_outage < WEIGHINGS, "stopped part-way through the queue"
        # What the client printed, not its queue file: a row's tries also count 429s before the outage.
        wait_for(
            lambda: output.text().count(UNREACHABLE) >= 2, "the client has retried against the dead service"
        )
        client.kill()  # ... and the station PC crashes while it retries
        client.wait(timeout=10)
        before_crash, crash_stderr = output.finish()

        # Started again at the default limit: the slow drain has done its part (the outage came
        # mid-queue), and the weighings left need not wait out a window each (~4 s a run).
        server.env = {k: v for k, v in server.env.items() if not k.startswith("TRIKECERT_STATION_RATE_")}
        server.start()
        restarted = subprocess.run(
            [*CLIENT, "send", *FAST_RETRIES], env=env, capture_output=True, text=True, timeout=120
        )
        assert restarted.returncode == 0, restarted.stdout + restarted.stderr
        report = subprocess.run([*CLIENT, "report"], env=env, capture_output=True, text=True)
    finally:
        server.stop()

    assert f"delivered #1     BDG 252 QH   inspection {first_id} (replayed)" in before_crash
    assert "Traceback" not in crash_stderr, "the client met the outage without a traceback"
    assert "Traceback" not in restarted.stderr
    assert count_inspections(session) == WEIGHINGS
    rows = queue_rows(queue)
    assert [row[2] for row in rows] == ["delivered"] * WEIGHINGS
    stored = set(session.scalars(select(Inspection.id)))
    assert {row[3] for row in rows} == stored, "each queued weighing is its own stored inspection"
    fronts = sorted(float(i.front_kg or 0) for i in session.scalars(select(Inspection)))
    assert fronts == [108 + i * 0.5 for i in range(WEIGHINGS)]
    assert f"{WEIGHINGS} delivered, 0 rejected, 0 pending" in report.stdout
    assert report.returncode == 0


def _first_queued(queue: Path) -> tuple[str, bytes]:
    with sqlite3.connect(queue) as connection:
        key, body = connection.execute(
            "SELECT idempotency_key, body FROM weighing ORDER BY id LIMIT 1"
        ).fetchone()
    return str(key), str(body).encode()


def _post(url: str, station_key: str, idempotency_key: str, body: bytes) -> int:
    request = urllib.request.Request(
        f"{url}/api/v1/inspections",
        data=body,
        headers={
            "Authorization": f"Bearer {station_key}",
            "Idempotency-Key": idempotency_key,
            "Content-Type": "application/json",
        },
        method="POST",
    )
    with urllib.request.urlopen(request, timeout=10) as response:
        assert response.status == 201
        inspection_id: int = json.loads(response.read())["id"]
        return inspection_id


def test_a_rejected_weighing_is_reported_with_the_servers_message_and_not_sent_again(
    database_url: str, session: Session, engine: Engine, tmp_path: Path
) -> None:
    _station_id, key = seed_station(session, "Roadside weighbridge")
    seed_study_vehicle(session)
    csv = tmp_path / "today.csv"
    csv.write_text(
        "registration_number,front_kg,left_rear_kg,right_rear_kg\n"
        "BDG 252 QH,108,115,135\n"
        "BDG 252 QH,100;108,115,135\n"
        "ZZZ 999 ZZ,108,115,135\n"
    )
    server = Server(database_url)
    env = dict(os.environ, TRIKECERT_STATION_KEY=key, TRIKECERT_STATION_QUEUE=str(tmp_path / "q.db"))
    server.start()
    try:
        first = subprocess.run(
            [*CLIENT, "--url", server.url, "submit", str(csv), *FAST_RETRIES],
            env=env,
            capture_output=True,
            text=True,
        )
        again = subprocess.run(
            [*CLIENT, "--url", server.url, "submit", str(csv), *FAST_RETRIES],
            env=env,
            capture_output=True,
            text=True,
        )
    finally:
        server.stop()

    assert first.returncode == 1, "some were rejected"
    assert "1 delivered, 2 rejected, 0 still queued" in first.stdout
    assert "422: readings.front_kg: the repeated readings of the front wheel" in first.stdout
    assert "404: registration_number: no vehicle ZZZ 999 ZZ is registered" in first.stdout
    assert "queued 0 weighing(s) (3 already queued)" in again.stdout
    assert "0 delivered, 0 rejected, 0 still queued" in again.stdout
    assert count_inspections(session) == 1
