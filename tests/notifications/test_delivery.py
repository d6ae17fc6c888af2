"""Delivery that loses nothing and spams no one: a gateway that answers 500, times out or hangs up and a
mail server that refuses are tried again with backoff; permanent refusals are recorded; a worker killed
mid-send and restarted sends the message again at most once; two workers never send one message twice."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Iterator
from datetime import timedelta
from pathlib import Path

import pytest
from served import free_port
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.db import get_sessionmaker, utcnow
from app.notifications.messages import Text
from app.notifications.models import NotificationDay, OutboxMessage
from app.notifications.service import enqueue
from app.notifications.worker import Pass, claim, run_once
from notifications.servers import Gateway, Mailbox, outside_services, senders

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def outside(monkeypatch: pytest.MonkeyPatch, engine: object) -> Iterator[tuple[Mailbox, Gateway]]:
    """The mail server and the SMS gateway, running, and the settings pointing at them."""
    with outside_services(monkeypatch, TRIKECERT_NOTIFY_INTERVAL_SECONDS="0.2") as running:
        yield running


def queue(session: Session, count: int, channel: str = "sms") -> list[int]:
    """`count` messages in the outbox, each with its own words."""
    made = []
    for n in range(count):
        recipient = f"+23480100000{n:02d}" if channel == "sms" else f"owner{n}@example.ng"
        message = enqueue(
            session,
            channel=channel,
            recipient=recipient,
            purpose="reply",
            text=Text("Subject" if channel == "email" else None, f"message number {n}"),
        )
        session.flush()
        made.append(message.id)
    session.commit()
    return made


def row(session: Session, message_id: int) -> OutboxMessage:
    session.expire_all()
    found = session.get(OutboxMessage, message_id)
    assert found is not None
    return found


def test_500_timeout_and_a_dropped_connection_are_tried_again_with_backoff(
    session: Session, outside: tuple[Mailbox, Gateway], caplog: pytest.LogCaptureFixture
) -> None:
    _mailbox, gateway = outside
    gateway.modes = ["500", "timeout", "drop"]
    gateway.slow = 2.0
    [message_id] = queue(session, 1)
    start = utcnow()
    results: list[Pass] = []
    for wait in (0, 30, 90, 210):
        results.append(
            run_once(
                get_sessionmaker(),
                senders(1),
                config.get_settings(),
                now=lambda w=wait: start + timedelta(seconds=w),  # type: ignore[misc]
            )
        )
    assert [r.retried for r in results] == [1, 1, 1, 0]
    assert results[-1].sent == 1
    sent = row(session, message_id)
    assert sent.sent_at is not None
    assert sent.attempts == 4
    assert sent.recipient is None
    assert sent.recipient_masked == "+234 80• ••• ••00"
    assert "Traceback" not in caplog.text
    # Not before its backoff: a pass 10 seconds after a failure leaves it waiting.
    gateway.modes = ["500"]
    [later] = queue(session, 1)
    run_once(get_sessionmaker(), senders(1), config.get_settings(), now=lambda: start)
    assert (
        run_once(
            get_sessionmaker(), senders(1), config.get_settings(), now=lambda: start + timedelta(seconds=10)
        ).sent
        == 0
    )
    assert row(session, later).attempts == 1


def test_a_permanent_refusal_and_too_many_failures_are_recorded_as_failed(
    session: Session, outside: tuple[Mailbox, Gateway], monkeypatch: pytest.MonkeyPatch
) -> None:
    mailbox, gateway = outside
    gateway.modes = ["refused"]
    mailbox.refuse = ["550 5.1.1 no such mailbox"]
    [sms_id] = queue(session, 1)
    [email_id] = queue(session, 1, channel="email")
    done = run_once(get_sessionmaker(), senders(1), config.get_settings())
    assert done.failed == 2
    for message_id in (sms_id, email_id):
        failed = row(session, message_id)
        assert failed.failed_at is not None
        assert failed.recipient is None
        assert failed.last_error
    monkeypatch.setenv("TRIKECERT_NOTIFY_MAX_ATTEMPTS", "2")
    config.get_settings.cache_clear()
    gateway.modes = ["500", "500"]
    [tired] = queue(session, 1)
    start = utcnow()
    run_once(get_sessionmaker(), senders(1), config.get_settings(), now=lambda: start)
    run_once(get_sessionmaker(), senders(1), config.get_settings(), now=lambda: start + timedelta(minutes=1))
    assert row(session, tired).failed_at is not None
    counts = {r.what: r.count for r in session.scalars(select(NotificationDay))}
    assert counts["failed"] == 3


def test_a_mail_server_that_refuses_for_now_or_is_down_is_tried_again(
    session: Session,
    outside: tuple[Mailbox, Gateway],
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    mailbox, _gateway = outside
    mailbox.refuse = ["451 4.3.0 try again later"]
    [message_id] = queue(session, 1, channel="email")
    start = utcnow()
    assert run_once(get_sessionmaker(), senders(1), config.get_settings(), now=lambda: start).retried == 1
    assert (
        run_once(
            get_sessionmaker(), senders(1), config.get_settings(), now=lambda: start + timedelta(minutes=1)
        ).sent
        == 1
    )
    assert mailbox.to("owner0@example.ng")[0].get_content().strip() == "message number 0"
    monkeypatch.setenv("TRIKECERT_SMTP_URL", f"smtp://127.0.0.1:{free_port()}")
    config.get_settings.cache_clear()
    [down] = queue(session, 1, channel="email")
    assert run_once(get_sessionmaker(), senders(1), config.get_settings()).retried == 1
    assert row(session, down).sent_at is None
    assert row(session, down).recipient is not None
    assert "Traceback" not in caplog.text
    del message_id


def _worker(*arguments: str) -> subprocess.Popen[bytes]:
    """`trikecert notify` in a process of its own, with the test's settings."""
    return subprocess.Popen(
        [sys.executable, "-m", "app.cli", "notify", *arguments],
        cwd=REPO,
        env={**os.environ},
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
    )


def test_a_worker_killed_mid_send_and_restarted_loses_nothing_and_sends_at_most_once_more(
    session: Session, outside: tuple[Mailbox, Gateway]
) -> None:
    _mailbox, gateway = outside
    gateway.modes = ["hang"]
    gateway.slow = 0.8  # the gateway accepts the first message but answers only after the worker is gone
    made = queue(session, 3)
    worker = _worker()
    try:
        assert gateway.arrived.wait(30), "the worker never sent"
        worker.send_signal(signal.SIGKILL)
        worker.wait(10)
    finally:
        if worker.poll() is None:
            worker.kill()
    assert row(session, made[0]).sent_at is None  # accepted by the gateway, never recorded
    time.sleep(3.2)  # the dead worker's claim lapses (2 x the timeout + 1 s)
    again = _worker("--once")
    output, _ = again.communicate(timeout=60)
    assert again.returncode == 0, output.decode()
    assert b"Traceback" not in output
    bodies = Counter(gateway.bodies())
    assert bodies["message number 0"] == 2  # the one duplicate the docs bound: the message in flight
    assert bodies["message number 1"] == 1
    assert bodies["message number 2"] == 1
    assert all(row(session, message_id).sent_at is not None for message_id in made)


def test_two_workers_at_once_never_send_one_message_twice(
    session: Session, outside: tuple[Mailbox, Gateway]
) -> None:
    _mailbox, gateway = outside
    gateway.delay = 0.05  # 40 sends take 2 s: the two workers overlap
    made = queue(session, 40)
    workers = [_worker("--once"), _worker("--once")]
    outputs = [worker.communicate(timeout=120)[0] for worker in workers]
    assert [worker.returncode for worker in workers] == [0, 0], outputs
    bodies = Counter(gateway.bodies())
    assert len(bodies) == 40
    assert set(bodies.values()) == {1}
    assert all(row(session, message_id).sent_at is not None for message_id in made)
    both = [output.count(b" sent to ") for output in outputs]
    assert sum(both) == 40
    print(f"the two workers sent {both}")


def test_a_claim_takes_exactly_one_message(session: Session, outside: tuple[Mailbox, Gateway]) -> None:
    """On PostgreSQL an `UPDATE ... WHERE id IN (SELECT ... SKIP LOCKED LIMIT 1)` claimed every row."""
    made = queue(session, 3)
    settings = config.get_settings()
    with get_sessionmaker()() as worker:
        first = claim(worker, {"sms"}, settings, utcnow())
        second = claim(worker, {"sms"}, settings, utcnow())
        assert first is not None
        assert second is not None
        assert (first.id, second.id) == (made[0], made[1])
    claimed = [row(session, message_id).claim for message_id in made]
    assert claimed[0] != claimed[1]
    assert claimed[2] is None
