"""The reminder planner asks the database the same few statements for one subscription as for fifty:
the work of a pass grows with the rows, not with round trips."""

from __future__ import annotations

import secrets
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from datetime import datetime, timedelta
from typing import Any

from fastapi.testclient import TestClient
from sqlalchemy import event, select
from sqlalchemy.orm import Session

from app import config
from app.certificates.models import Certificate
from app.db import utcnow
from app.notifications.contacts import digest
from app.notifications.languages import choose_language
from app.notifications.models import OutboxMessage, Subscription
from app.notifications.service import plan_reminders
from notifications.phone_helpers import certify, weigh

PLATES = ("KTU 417 XA", "LAG 100 RV", "ABJ 200 SP", "KAN 300 EX")


@contextmanager
def statements(session: Session) -> Iterator[list[str]]:
    """Every SQL statement sent to the database meanwhile, as the driver received it."""
    seen: list[str] = []
    engine = session.get_bind()

    def count(_conn: Any, _cursor: Any, sql: str, *_args: Any) -> None:
        seen.append(sql)

    event.listen(engine, "before_cursor_execute", count)
    try:
        yield seen
    finally:
        event.remove(engine, "before_cursor_execute", count)


def subscriber(session: Session, vehicle_id: int, index: int) -> Subscription:
    """A confirmed subscription: even ones by SMS, odd ones by email; every fourth phone chose Hausa."""
    channel = "sms" if index % 2 == 0 else "email"
    contact = f"+23480{index:08d}" if channel == "sms" else f"owner{index}@example.ng"
    if channel == "sms" and index % 4 == 0:
        choose_language(session, contact, "ha")
    subscription = Subscription(
        vehicle_id=vehicle_id,
        channel=channel,
        contact=contact,
        contact_digest=digest(contact),
        token=secrets.token_urlsafe(32),
        confirmed_at=utcnow(),
        created_at=utcnow(),
        language="yo" if index % 3 == 0 else None,
    )
    session.add(subscription)
    return subscription


def test_planning_reminders_takes_as_many_statements_for_fifty_subscriptions_as_for_one(
    api: TestClient, session: Session
) -> None:
    numbers = [certify(api, weigh(api, plate)) for plate in PLATES]
    certificates = session.scalars(select(Certificate).where(Certificate.number.in_(numbers))).all()
    vehicles = [certificate.vehicle_id for certificate in certificates]
    expires = min(certificate.expires_at for certificate in certificates)
    settings = config.get_settings()

    def plan(at: datetime) -> tuple[int, list[str]]:
        session.expire_all()
        with statements(session) as seen:
            written = plan_reminders(session, settings, now=at)
        return written, seen

    subscriber(session, vehicles[0], 0)
    session.commit()
    one, one_due = plan(expires - timedelta(days=20))
    assert one == 1
    _, one_done = plan(expires - timedelta(days=19))  # its reminder already written

    for index in range(1, 50):
        subscriber(session, vehicles[index % len(vehicles)], index)
    session.commit()
    fifty, fifty_due = plan(expires - timedelta(days=3))
    assert fifty == 50
    _, fifty_done = plan(expires - timedelta(days=2))

    assert len(fifty_due) == len(one_due), (one_due, fifty_due)
    assert len(fifty_done) == len(one_done), (one_done, fifty_done)
    assert len(one_due) <= 8, one_due
    written: Callable[[str], int] = lambda stage: len(  # noqa: E731
        session.scalars(select(OutboxMessage.id).where(OutboxMessage.purpose == stage)).all()
    )
    assert (written("reminder_30"), written("reminder_7")) == (1, 50)
