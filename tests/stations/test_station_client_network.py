"""Done when: whatever the network does, the station client retries with backoff, counts each failed
try by its cause, honours Retry-After, stores each weighing exactly once, and never stops with a
traceback. The real `trikecert-station` process against a fake service on a raw socket that refuses,
resets, cuts answers short, stays silent, and answers 5xx, 408, 409 and 429 before it stores."""

from __future__ import annotations

import json
import os
import re
import sqlite3
import subprocess
import sys
from pathlib import Path

from fake_station_service import (
    FakeStationService,
    answer,
    created,
    cut_off,
    refusal,
    reset_mid_request,
    silent,
    stalls_mid_answer,
)

CLIENT = [sys.executable, "-m", "app.station_client"]
FAST = ["--backoff-base", "0.01", "--backoff-cap", "0.05", "--timeout", "0.5", "--give-up-after", "60"]
IN_FLIGHT = "Idempotency-Key: a request with this key is still being processed"


def client_env(queue: Path, url: str) -> dict[str, str]:
    return dict(
        os.environ,
        TRIKECERT_STATION_KEY="tks_fake",
        TRIKECERT_STATION_QUEUE=str(queue),
        TRIKECERT_STATION_URL=url,
        PYTHONUNBUFFERED="1",
    )


def queue_two(tmp_path: Path, env: dict[str, str]) -> list[tuple[int, str, str, str, int | None, int]]:
    csv = tmp_path / "today.csv"
    csv.write_text("registration_number,front_kg,left_rear_kg,right_rear_kg\nBDG 252 QH,108,115,135\n"
                   "BDG 252 QH,108.5,115,135\n")  # fmt: skip
    queued = subprocess.run([*CLIENT, "queue", str(csv)], env=env, capture_output=True, text=True)
    assert queued.returncode == 0, queued.stderr
    return rows(Path(env["TRIKECERT_STATION_QUEUE"]))


def rows(queue: Path) -> list[tuple[int, str, str, str, int | None, int]]:
    with sqlite3.connect(queue) as connection:
        found = connection.execute(
            "SELECT id, idempotency_key, body, state, inspection_id, attempts FROM weighing ORDER BY id"
        ).fetchall()
    return [tuple(row) for row in found]


def failed_tries(stdout: str) -> dict[str, int]:
    """The run's count of tries without a final answer, by cause, from its summary line."""
    match = re.search(r"^(\d+) tries without a final answer \(retried or left queued\): (.+)$", stdout, re.M)
    assert match, stdout
    counts = {cause: int(n) for n, cause in re.findall(r"(\d+) ([^,]+)(?:, |$)", match[2])}
    assert sum(counts.values()) == int(match[1])
    return counts


def test_every_failure_of_the_network_is_retried_and_counted_and_each_weighing_stored_once(
    tmp_path: Path,
) -> None:
    script = [
        reset_mid_request,
        cut_off("503 Service Unavailable", "the database is unavailable"),  # the service died sending it
        silent,  # no answer within --timeout
        stalls_mid_answer,  # a 201's head, then nothing within --timeout
        answer("500 Internal Server Error", b"Internal Server Error", {"Content-Type": "text/plain"}),
        answer("502 Bad Gateway", b"<html><body>Bad Gateway</body></html>", {"Content-Type": "text/html"}),
        refusal("408 Request Timeout", "the request took too long to arrive"),
        refusal("409 Conflict", IN_FLIGHT, {"Retry-After": "1"}),
        refusal("429 Too Many Requests", "too many requests for this station key", {"Retry-After": "1"}),
        created(),  # the first weighing is stored
        created(cut_after=5),  # the second is stored, and its answer lost on the way back
        created(),  # ... so the retry gets the stored answer replayed
    ]
    service = FakeStationService(script)
    env = client_env(tmp_path / "queue.db", service.url)
    (first, second) = queue_two(tmp_path, env)
    client = subprocess.Popen(
        [*CLIENT, "send", *FAST], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert client.stdout is not None
        before = [client.stdout.readline()]  # the service is not listening yet: connection refused
        service.listen()
        after, stderr = client.communicate(timeout=120)
    finally:
        client.kill()
        service.close()
    stdout = before[0] + after

    assert client.returncode == 0, stdout + stderr
    assert stderr == "", "no traceback, no warning: every failure was expected"
    assert "the service could not be reached: connection refused" in before[0]
    assert "2 delivered, 0 rejected, 0 still queued" in stdout
    counts = failed_tries(stdout)
    assert counts.pop("connection refused") >= 1
    assert counts == {
        "reset": 1,
        "cut off": 2,
        "timed out": 2,
        "5xx": 2,
        "408 request timeout": 1,
        "409 in flight": 1,
        "429 too many requests": 1,
    }
    # Each try of a weighing carries its own Idempotency-Key and the same body; the service stored two.
    keys = [request.idempotency_key for request in service.requests]
    assert keys == [first[1]] * 10 + [second[1]] * 2
    assert all(request.body == first[2].encode() for request in service.requests[1:10])
    assert service.stored == {first[1]: 100, second[1]: 101}
    assert [row[3:5] for row in rows(tmp_path / "queue.db")] == [("delivered", 100), ("delivered", 101)]
    assert "inspection 101 (replayed)" in stdout
    # Retry-After was honoured (the backoff alone would have waited at most 0.05 s).
    for index in (7, 8):
        waited = service.requests[index + 1].received_at - service.sending_at[index]
        assert waited >= 1.0 - 1e-3, f"retried {waited:.3f} s after a Retry-After: 1"
    assert f"409: {IN_FLIGHT}; retry in 1.0 s" in stdout
    assert "429: too many requests for this station key; retry in 1.0 s" in stdout
    assert "the answer was cut off after" in stdout


def test_a_service_that_never_answers_leaves_everything_queued_and_says_so(tmp_path: Path) -> None:
    service = FakeStationService([])  # bound, never listening
    env = client_env(tmp_path / "queue.db", service.url)
    queue_two(tmp_path, env)
    try:
        sent = subprocess.run(
            [*CLIENT, "send", "--backoff-base", "0.01", "--backoff-cap", "0.05", "--give-up-after", "0.2"],
            env=env, capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    finally:
        service.close()
    assert sent.returncode == 3, "some still queued"
    assert "Traceback" not in sent.stderr
    assert "stopped: gave up after 0.2 s without an answer" in sent.stderr
    assert "0 delivered, 0 rejected, 2 still queued" in sent.stdout
    assert failed_tries(sent.stdout)["connection refused"] >= 1
    assert [row[3] for row in rows(tmp_path / "queue.db")] == ["pending", "pending"]


def test_a_rejected_weighing_is_sent_again_by_retry_once_its_cause_is_fixed(tmp_path: Path) -> None:
    unknown = "registration_number: no vehicle BDG 252 QH is registered"
    refusing = FakeStationService([refusal("404 Not Found", unknown), created()])
    env = client_env(tmp_path / "queue.db", refusing.url)
    (first, _second) = queue_two(tmp_path, env)
    refusing.listen()
    try:
        sent = subprocess.run([*CLIENT, "send", *FAST], env=env, capture_output=True, text=True, timeout=60)
        report = subprocess.run([*CLIENT, "report"], env=env, capture_output=True, text=True)
    finally:
        refusing.close()
    assert sent.returncode == 1, "some rejected"
    assert f"rejected  #1     BDG 252 QH   404: {unknown}; once the cause is fixed, send it again with: " \
           "trikecert-station retry 1" in sent.stdout  # fmt: skip
    assert "once a rejection's cause is fixed, send it again with: trikecert-station retry ID" in sent.stdout
    assert "trikecert-station retry 1" in report.stdout

    # The vehicle is registered now: the same weighing, under the same key, is stored.
    fixed = FakeStationService([created()])
    fixed.listen()
    try:
        retried = subprocess.run(
            [*CLIENT, "retry", "#1", "--url", fixed.url, *FAST], env=env, capture_output=True, text=True,
            timeout=60,
        )  # fmt: skip
    finally:
        fixed.close()
    assert retried.returncode == 0, retried.stdout + retried.stderr
    assert f"queued again #1 BDG 252 QH (rejected before: 404: {unknown})" in retried.stdout
    assert "1 delivered, 0 rejected, 0 still queued" in retried.stdout
    assert [request.idempotency_key for request in fixed.requests] == [first[1]]
    assert [json.loads(request.body) for request in fixed.requests] == [json.loads(first[2])]
    assert [row[3] for row in rows(tmp_path / "queue.db")] == ["delivered", "delivered"]

    # Delivered is final: retrying it again sends nothing (this service would refuse any connection).
    closed = FakeStationService([])
    try:
        again = subprocess.run(
            [*CLIENT, "retry", "1", "--url", closed.url, *FAST], env=env, capture_output=True, text=True,
            timeout=60,
        )  # fmt: skip
        unknown_id = subprocess.run(
            [*CLIENT, "retry", "7", "--url", closed.url], env=env, capture_output=True, text=True, timeout=60
        )
    finally:
        closed.close()
    assert again.returncode == 0, again.stdout + again.stderr
    assert "not sent again: #1 was delivered as inspection 100" in again.stdout
    assert "0 delivered, 0 rejected, 0 still queued" in again.stdout
    assert unknown_id.returncode == 2
    assert "no weighing #7 in the queue" in unknown_id.stderr
    assert "Traceback" not in again.stderr + unknown_id.stderr
