"""Reminders from subscription to the after-expiry one, through a real SMTP server and a local send API:
confirmed first, 30 days and 7 days before, a day after, each once; stopped by the link and by STOP."""

from __future__ import annotations

import re
from collections.abc import Iterator
from datetime import datetime, timedelta

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.db import get_sessionmaker, utcnow
from app.notifications.models import NotificationDay, OutboxMessage, Subscription
from app.notifications.sms_text import fits_sms
from app.notifications.worker import Pass, run_once
from app.trust.numbers import parse_number
from notifications.phone_helpers import PHONE, SMS, certify, weigh
from notifications.servers import Gateway, Mailbox, outside_services, senders

EMAIL = "Ada.Obi@Example.NG"


@pytest.fixture
def outside(monkeypatch: pytest.MonkeyPatch, gateway_on: None) -> Iterator[tuple[Mailbox, Gateway]]:
    """The mail server and the SMS gateway, running, and the settings pointing at them."""
    with outside_services(monkeypatch, TRIKECERT_AFRICASTALKING_SENDER="TRIKECERT") as running:
        yield running


def worker_pass(at: datetime) -> Pass:
    """One pass of the worker with its clock at `at`."""
    return run_once(get_sessionmaker(), senders(2), config.get_settings(), now=lambda: at)


def sms_in(client: TestClient, text: str, message_id: str) -> None:
    response = client.post(
        SMS,
        data={
            "from": PHONE,
            "to": "12345",
            "text": text,
            "date": "2026-12-03",
            "id": message_id,
            "linkId": "",
        },
    )
    assert response.status_code == 200, response.text


def subscribe_by_email(client: TestClient, plate: str, email: str = EMAIL) -> str:
    form = client.get("/reminders")
    assert form.status_code == 200
    assert "<script" not in form.text
    token = re.search(r'name="csrf_token" value="([^"]+)"', form.text)
    assert token is not None
    done = client.post("/reminders", data={"csrf_token": token[1], "plate": plate, "email": email})
    assert done.status_code == 200, done.text
    return done.text


def test_the_full_cycle_by_email_and_by_sms(
    api: TestClient, client: TestClient, session: Session, outside: tuple[Mailbox, Gateway]
) -> None:
    mailbox, gateway = outside
    number = certify(api, weigh(api, "KTU 417 XA"))
    api.headers.pop("Authorization")
    page = subscribe_by_email(client, "ktu417xa")
    assert "We sent a link to A•••@example.ng" in page
    assert "Ada.Obi" not in page
    sms_in(client, "REMIND KTU 417 XA", "in-1")

    expires = _expiry(session, number)
    now = utcnow()
    assert worker_pass(now).sent == 2  # the two confirmations, nothing else
    address = "Ada.Obi@example.ng"
    [confirmation] = mailbox.to(address)
    link = re.search(r"http://\S+/reminders/confirm/(\S+)", confirmation.get_content())
    assert link is not None
    [code_sms] = gateway.received
    assert code_sms["to"] == PHONE
    assert code_sms["from"] == "TRIKECERT"
    assert code_sms["apiKey"] == "at-test-key"
    code = re.search(r"code (\d{6})", code_sms["message"])
    assert code is not None
    assert fits_sms(code_sms["message"])

    # Nothing but the confirmation goes out before it is confirmed, even when a reminder is due.
    assert worker_pass(expires - timedelta(days=29)).sent == 0
    confirmed = client.get(f"/reminders/confirm/{link[1]}")
    assert confirmed.status_code == 200, (link[1], confirmed.text)
    sms_in(client, f"yes {code[1]}", "in-2")
    worker_pass(utcnow())
    assert "Reminders for KTU 417 XA confirmed" in gateway.bodies()[-1]

    before = len(mailbox.messages), len(gateway.received)
    assert worker_pass(expires - timedelta(days=31)).sent == 0
    thirty = worker_pass(expires - timedelta(days=30))
    assert thirty.sent == 2
    assert worker_pass(expires - timedelta(days=29)).sent == 0  # at most once per expiry
    seven = worker_pass(expires - timedelta(days=7))
    assert seven.sent == 2
    assert worker_pass(expires - timedelta(days=1)).sent == 0
    assert worker_pass(expires + timedelta(hours=12)).sent == 0  # not yet a day after
    assert worker_pass(expires + timedelta(days=1)).sent == 2
    assert worker_pass(expires + timedelta(days=2)).sent == 0
    emails = mailbox.to(address)[1:]
    texts = gateway.bodies()[before[1] :]
    assert len(emails) == 3
    assert len(texts) == 3
    assert "runs out in 30 days" in emails[0]["Subject"]
    assert "runs out in 7 days" in emails[1]["Subject"]
    assert "EXPIRED on" in emails[2]["Subject"]
    assert all(text.endswith("Reply STOP to end.") and fits_sms(text) for text in texts)
    assert f"KTU 417 XA: Certificate {number} runs out in 30 days." in texts[0]
    unsubscribe = emails[2]["List-Unsubscribe"]
    assert emails[2]["List-Unsubscribe-Post"] == "List-Unsubscribe=One-Click"
    assert unsubscribe.startswith("<http")
    assert "/reminders/unsubscribe/" in unsubscribe
    assert unsubscribe.strip("<>") in emails[2].get_content()

    # Unsubscribe by the link (a mail program's one-click POST), and by STOP.
    path = "/reminders/unsubscribe/" + unsubscribe.strip("<>").rsplit("/", 1)[1]
    assert "Stop the reminders" in client.get(path).text  # opening the link alone stops nothing
    assert session.scalar(select(Subscription).where(Subscription.channel == "email")) is not None
    assert client.post(path).status_code == 200
    sms_in(client, "STOP", "in-3")
    session.expire_all()
    assert session.scalars(select(Subscription)).all() == []
    stored = session.scalars(select(OutboxMessage)).all()
    assert all(row.recipient is None for row in stored if row.sent_at is not None)
    assert not any(address in (row.recipient or "") for row in stored)
    counts = {row.what: row.count for row in session.scalars(select(NotificationDay))}
    assert counts.get("subscribed", 0) + counts.get("unsubscribed", 0) >= 2


def _expiry(session: Session, number: str) -> datetime:
    from app.certificates.models import Certificate

    found = session.scalar(
        select(Certificate.expires_at).where(Certificate.number == str(parse_number(number)))
    )
    assert found is not None
    return found


def test_a_new_certificate_starts_a_new_cycle(
    api: TestClient, client: TestClient, session: Session, outside: tuple[Mailbox, Gateway]
) -> None:
    _mailbox, gateway = outside
    first = certify(api, weigh(api, "KTU 417 XA"))
    sms_in(client, "REMIND KTU417XA", "in-1")
    worker_pass(utcnow())
    code = re.search(r"code (\d{6})", gateway.bodies()[-1])
    assert code is not None
    sms_in(client, code[1], "in-2")  # the code alone confirms too
    worker_pass(utcnow())
    assert "confirmed" in gateway.bodies()[-1]
    old_expiry = _expiry(session, first)
    assert worker_pass(old_expiry - timedelta(days=30)).sent == 1
    second = certify(api, weigh(api, "KTU 417 XA", register=False))
    new_expiry = _expiry(session, second)
    assert worker_pass(new_expiry - timedelta(days=30)).sent == 1
    assert second in gateway.bodies()[-1]
    assert first not in gateway.bodies()[-1]
    assert worker_pass(new_expiry - timedelta(days=29)).sent == 0


def test_a_refusal_triggers_no_reminder(
    api: TestClient, client: TestClient, session: Session, outside: tuple[Mailbox, Gateway]
) -> None:
    mailbox, _gateway = outside
    refusal = certify(api, weigh(api, "BDG 252 QH", stable=False))
    api.headers.pop("Authorization")
    subscribe_by_email(client, "BDG 252 QH")
    worker_pass(utcnow())
    link = re.search(r"/reminders/confirm/(\S+)", mailbox.messages[-1].get_content())
    assert link is not None
    client.get(f"/reminders/confirm/{link[1]}")
    expires = _expiry(session, refusal)
    for days in (30, 7, -1):
        assert worker_pass(expires - timedelta(days=days)).planned == 0
    assert len(mailbox.messages) == 1
