"""How the station client treats each answer: delivered, rejected for good with the server's message,
or retried with capped, jittered exponential backoff that honours Retry-After; a refused key stops
the run with everything still queued."""

from __future__ import annotations

import random
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest

from app.station_client.delivery import Backoff, deliver
from app.station_client.files import Weighing
from app.station_client.http import Answer, Verdict, judge, retry_after_seconds
from app.station_client.outbox import Outbox, Queued

CREATED = b'{"id": 17, "registration_number": "BDG 252 QH"}'


def refusal(detail: str) -> bytes:
    return f'{{"detail": "{detail}", "errors": []}}'.encode()


@pytest.mark.parametrize(
    ("status", "headers", "body", "verdict"),
    [
        (201, {}, CREATED, Verdict.DELIVERED),
        (201, {"Idempotent-Replayed": "true"}, CREATED, Verdict.DELIVERED),
        (201, {}, b"<html>captive portal</html>", Verdict.RETRY),
        (422, {}, refusal("readings.front_kg: the scale had not settled"), Verdict.REJECTED),
        (403, {}, refusal("calibration lapsed"), Verdict.REJECTED),
        (404, {}, refusal("registration_number: not registered"), Verdict.REJECTED),
        (401, {}, refusal("Authorization: not recognised"), Verdict.UNAUTHORIZED),
        (409, {"Retry-After": "1"}, refusal("still being processed"), Verdict.RETRY),
        (429, {"Retry-After": "7"}, refusal("too many"), Verdict.RETRY),
        (500, {}, b"Internal Server Error", Verdict.RETRY),
        (503, {}, b"", Verdict.RETRY),
    ],
)
def test_each_answer_has_its_verdict(
    status: int, headers: dict[str, str], body: bytes, verdict: Verdict
) -> None:
    answer = judge(status, headers, body)
    assert answer.verdict is verdict
    if verdict is Verdict.DELIVERED:
        assert answer.inspection_id == 17
        assert answer.replayed == ("Idempotent-Replayed" in headers)
    if status in (422, 403, 404):
        assert answer.message == body.decode().split('"')[3], "the server's own message"
    if status == 429:
        assert answer.retry_after == 7


def test_retry_after_may_be_seconds_or_a_date() -> None:
    now = datetime(2026, 11, 23, 15, 0, 0, tzinfo=UTC)
    assert retry_after_seconds("120") == 120
    assert retry_after_seconds("Mon, 23 Nov 2026 15:00:30 GMT", now=now) == 30
    assert retry_after_seconds("soon") is None
    assert retry_after_seconds(None) is None


def test_backoff_doubles_with_jitter_up_to_its_cap_and_honours_retry_after() -> None:
    backoff = Backoff(base=0.5, cap=8.0, rng=random.Random(5))
    for attempt, ceiling in [(0, 0.5), (1, 1.0), (2, 2.0), (3, 4.0), (4, 8.0), (10, 8.0), (500, 8.0)]:
        delays = {backoff.delay(attempt) for _ in range(20)}
        assert all(ceiling / 2 <= d <= ceiling for d in delays)
        assert len(delays) > 1, "jittered, so stations that lost the link together do not retry together"
    assert backoff.delay(0, retry_after=30) == 30


class FakeService:
    """Answers from a script, one per try; records what was sent."""

    def __init__(self, answers: list[Answer]) -> None:
        self.answers: Iterator[Answer] = iter(answers)
        self.sent: list[str] = []

    def __call__(self, weighing: Queued) -> Answer:
        self.sent.append(weighing.idempotency_key)
        return next(self.answers)


@pytest.fixture
def outbox(tmp_path: Path) -> Iterator[Outbox]:
    box = Outbox(tmp_path / "queue.db")
    box.enqueue([Weighing({"registration_number": f"REG{i}", "readings": {}}) for i in range(3)])
    yield box
    box.close()


def unreachable() -> Answer:
    return Answer(Verdict.RETRY, None, "the service could not be reached: connection refused")


def test_the_client_retries_through_an_outage_then_reports_delivered_and_rejected(outbox: Outbox) -> None:
    service = FakeService(
        [
            unreachable(),
            Answer(Verdict.RETRY, 503, "down for maintenance"),
            Answer(Verdict.RETRY, 429, "too many", retry_after=5),
            Answer(Verdict.DELIVERED, 201, "stored", inspection_id=41),
            Answer(Verdict.REJECTED, 422, "readings.front_kg: the scale had not settled"),
            Answer(Verdict.DELIVERED, 201, "stored", inspection_id=41, replayed=True),
        ]
    )
    waits: list[float] = []
    report = deliver(
        outbox, send=service, backoff=Backoff(base=1, cap=4, rng=random.Random(1)), give_up_after=60,
        sleep=waits.append, clock=lambda: sum(waits), say=lambda _line: None,
    )  # fmt: skip

    first, second, third = outbox.every()
    assert service.sent == [first.idempotency_key] * 4 + [second.idempotency_key, third.idempotency_key]
    assert len(waits) == 3
    assert waits[2] == 5, "the 429's Retry-After is honoured"
    assert (first.state, first.inspection_id, first.attempts) == ("delivered", 41, 4)
    assert (second.state, second.http_status, second.message) == (
        "rejected", 422, "readings.front_kg: the scale had not settled"
    )  # fmt: skip
    assert third.state == "delivered"
    assert [q.id for q, _ in report.delivered] == [first.id, third.id]
    assert report.pending == []
    assert report.stopped is None


def test_the_client_gives_up_for_now_and_keeps_the_rest_queued(outbox: Outbox) -> None:
    waits: list[float] = []
    report = deliver(
        outbox, send=FakeService([unreachable()] * 50), backoff=Backoff(base=1, cap=4), give_up_after=10,
        sleep=waits.append, clock=lambda: sum(waits), say=lambda _line: None,
    )  # fmt: skip
    assert sum(waits) <= 10
    assert report.stopped is not None
    assert "gave up after 10 s" in report.stopped
    assert len(report.pending) == 3
    assert outbox.every()[0].attempts == len(waits) + 1


def test_a_refused_station_key_stops_the_run_and_loses_nothing(outbox: Outbox) -> None:
    report = deliver(
        outbox, send=FakeService([Answer(Verdict.UNAUTHORIZED, 401, "key not recognised")]),
        backoff=Backoff(), give_up_after=60, sleep=lambda _s: None, say=lambda _line: None,
    )  # fmt: skip
    assert report.stopped is not None
    assert "refused the station key" in report.stopped
    assert [q.state for q in outbox.every()] == ["pending"] * 3


def test_a_retry_after_beyond_the_give_up_time_stops_the_run_and_says_why(outbox: Outbox) -> None:
    slept: list[float] = []
    report = deliver(
        outbox, send=FakeService([Answer(Verdict.RETRY, 429, "too many", retry_after=3600, cause="429")]),
        backoff=Backoff(), give_up_after=60, sleep=slept.append, clock=lambda: 0.0, say=lambda _line: None,
    )  # fmt: skip
    assert slept == [], "it does not sleep an hour"
    assert report.stopped == "gave up after 60 s without an answer (it asked to wait 3600 s): too many"
    assert report.failed_tries == {"429": 1}
    assert len(report.pending) == 3
