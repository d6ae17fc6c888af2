"""Done when: 20 concurrent retries with one Idempotency-Key store exactly one inspection, every answer
being the same 201 or a 409; and the rate limit holds across workers. Both against a real
`trikecert serve --workers 2`, on whichever database the run uses (SQLite or PostgreSQL)."""

from __future__ import annotations

import json
import threading
import urllib.error
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import pytest
from sqlalchemy import Engine, select
from sqlalchemy.orm import Session
from station_server import Server, count_inspections, seed_station, seed_study_vehicle

from app.inspections.models import Inspection
from app.stations.models import StationRateWindow

RATE_LIMIT = 30
STUDY_BODY = {
    "registration_number": "BDG 252 QH",
    "readings": {"front_kg": [108, 108.5], "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
}


@dataclass(frozen=True)
class Answer:
    status: int
    body: bytes
    headers: dict[str, str]

    def json(self) -> Any:
        return json.loads(self.body)


def _lower(items: Any) -> dict[str, str]:
    return {name.lower(): value for name, value in items}


def call(
    url: str, key: str, *, body: dict[str, Any] | None = None, idempotency_key: str | None = None
) -> Answer:
    headers = {"Authorization": f"Bearer {key}", "Content-Type": "application/json"}
    if idempotency_key:
        headers["Idempotency-Key"] = idempotency_key
    data = json.dumps(body).encode() if body is not None else None
    request = urllib.request.Request(url, data=data, headers=headers, method="POST" if data else "GET")
    try:
        with urllib.request.urlopen(request, timeout=30) as response:
            return Answer(response.status, response.read(), _lower(response.headers.items()))
    except urllib.error.HTTPError as error:
        with error:
            return Answer(error.code, error.read(), _lower(error.headers.items()))


def all_at_once(count: int, job: Any) -> list[Answer]:
    """Run `job()` on `count` threads released together; their answers."""
    barrier = threading.Barrier(count)
    answers: list[Answer] = []
    lock = threading.Lock()

    def run() -> None:
        barrier.wait()
        answer = job()
        with lock:
            answers.append(answer)

    threads = [threading.Thread(target=run) for _ in range(count)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=60)
    return answers


@pytest.fixture(scope="module")
def server(database_url: str) -> Iterator[Server]:
    """Two workers; a rate limit of RATE_LIMIT requests per station per hour."""
    running = Server(
        database_url,
        workers=2,
        env={
            "TRIKECERT_STATION_RATE_LIMIT": str(RATE_LIMIT),
            "TRIKECERT_STATION_RATE_WINDOW_SECONDS": "3600",
        },
    )
    running.start()
    yield running
    running.stop()


def test_twenty_concurrent_retries_with_one_key_store_one_inspection(
    server: Server, session: Session, engine: Engine
) -> None:
    _station_id, key = seed_station(session, "Concurrent weighbridge")
    seed_study_vehicle(session)
    url = f"{server.url}/api/v1/inspections"

    answers = all_at_once(20, lambda: call(url, key, body=STUDY_BODY, idempotency_key="weighing-0001"))

    assert len(answers) == 20
    assert {a.status for a in answers} <= {201, 409}, [(a.status, a.body[:200]) for a in answers]
    created = [a for a in answers if a.status == 201]
    assert created, "at least the first request is stored"
    assert len({a.body for a in created}) == 1, "every 201 is the same answer"
    assert sum("idempotent-replayed" not in a.headers for a in created) == 1, "one original, the rest replays"
    for conflict in (a for a in answers if a.status == 409):
        assert conflict.json()["errors"][0]["rule"] == "idempotency_key_in_flight"
        assert int(conflict.headers["retry-after"]) >= 1
    assert count_inspections(session) == 1
    stored_id = session.scalar(select(Inspection.id))
    assert created[0].json()["id"] == stored_id

    again = call(url, key, body=STUDY_BODY, idempotency_key="weighing-0001")
    assert (again.status, again.body, again.headers.get("idempotent-replayed")) == (
        201,
        created[0].body,
        "true",
    )
    assert count_inspections(session) == 1


def test_the_rate_limit_holds_across_two_workers(server: Server, session: Session, engine: Engine) -> None:
    station_id, key = seed_station(session, "Busy weighbridge")
    _other_id, other_key = seed_station(session, "Quiet weighbridge")
    url = f"{server.url}/api/v1/inspections"

    answers = all_at_once(RATE_LIMIT + 10, lambda: call(url, key))

    statuses = sorted(a.status for a in answers)
    assert statuses == [200] * RATE_LIMIT + [429] * 10
    for refused in (a for a in answers if a.status == 429):
        assert 1 <= int(refused.headers["retry-after"]) <= 3600
        assert refused.json()["errors"][0] == {
            "field": "Authorization",
            "rule": "rate_limit",
            "message": refused.json()["detail"],
        }
    session.expire_all()
    window = session.get(StationRateWindow, station_id)
    assert window is not None
    assert window.request_count == RATE_LIMIT + 10
    assert call(url, other_key).status == 200, "another station's key has its own window"
