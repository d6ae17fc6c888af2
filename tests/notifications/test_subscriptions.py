"""Subscriptions: contacts normalised and masked, never shown or logged in clear; confirmation limits per
contact, per client address and per phone; the /reminders form's bad input; admins see counts only."""

from __future__ import annotations

import re

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.audit.models import AuditEvent
from app.notifications.contacts import (
    ContactRefused,
    mask_email,
    mask_phone,
    normalise_email,
    normalise_phone,
)
from app.notifications.models import OutboxMessage, Subscription
from app.notifications.sms_text import fits_sms, sms_limit, sms_units
from notifications.phone_helpers import PHONE, USSD, certify, weigh

pytestmark = pytest.mark.usefixtures("gateway_on")


@pytest.mark.parametrize(
    ("written", "e164"),
    [
        ("+234 801 234 5667", "+2348012345667"),
        ("08012345667", "+2348012345667"),
        ("002348012345667", "+2348012345667"),
        ("2348012345667", "+2348012345667"),
        ("+254 712 345 678", "+254712345678"),
    ],
)
def test_phone_numbers_are_normalised_to_e164(written: str, e164: str) -> None:
    assert normalise_phone(written) == e164


@pytest.mark.parametrize("written", ["", "12", "+234 80x 234", "٠٨٠١٢٣٤٥٦٦٧", "+" + "9" * 20, "0" * 12])
def test_what_is_no_phone_number_is_refused(written: str) -> None:
    with pytest.raises(ContactRefused):
        normalise_phone(written)


def test_contacts_are_masked_as_the_issue_shows() -> None:
    assert mask_phone("+2348012345667") == "+234 80• ••• ••67"
    assert mask_email(normalise_email("Ada.Obi@Example.NG")) == "A•••@example.ng"
    with pytest.raises(ContactRefused):
        normalise_email("not an address")


def test_sms_length_counts_gsm7_extension_characters_twice_and_unicode_at_70() -> None:
    assert sms_units("a€") == 3
    assert sms_limit("a€") == 160
    assert sms_limit("Ọ̀yọ́") == 70
    assert fits_sms("Ọ̀yọ́")
    assert not fits_sms("x" * 161)
    assert fits_sms("x" * 160)


def _ussd(client: TestClient, text: str, phone: str = PHONE) -> str:
    response = client.post(
        USSD, data={"sessionId": "s1", "serviceCode": "*384#", "phoneNumber": phone, "text": text}
    )
    assert response.status_code == 200
    return response.text


def test_ussd_reminders_ask_for_a_code_then_stop_deletes_the_number(
    api: TestClient, client: TestClient, session: Session, caplog: pytest.LogCaptureFixture
) -> None:
    certify(api, weigh(api, "KTU 417 XA"))
    assert _ussd(client, "2") == "CON Enter the plate to be reminded about"
    answer = _ussd(client, "2*ktu 417 xa")
    assert (
        answer == "END A code was sent by SMS to +234 80• ••• ••67. "
        "Reply YES and the code to confirm reminders for KTU 417 XA."
    )
    [confirm] = session.scalars(select(OutboxMessage)).all()
    assert confirm.purpose == "confirm"
    assert fits_sms(confirm.body)
    assert _ussd(client, "2*ZZZ 1").startswith("END No keke ZZZ 1 is registered")
    assert (
        _ussd(client, "3")
        == "END Reminders to +234 80• ••• ••67 stopped (1 plate). Nothing more will be sent."
    )
    session.expire_all()
    assert session.scalars(select(Subscription)).all() == []
    assert session.scalars(select(OutboxMessage).where(OutboxMessage.sent_at.is_(None))).all() == []
    assert "8012345667" not in caplog.text
    events = session.scalars(select(AuditEvent)).all()
    assert not any("8012345667" in str(vars(event)) for event in events)


def test_confirmation_codes_are_limited_per_contact_and_per_client_address(
    api: TestClient, client: TestClient, session: Session
) -> None:
    certify(api, weigh(api, "KTU 417 XA"))
    for _ in range(3):
        assert _ussd(client, "2*KTU417XA").startswith("END A code was sent")
    assert (
        _ussd(client, "2*KTU417XA") == "END Too many codes were sent to this phone today: try again tomorrow."
    )
    assert len(session.scalars(select(OutboxMessage)).all()) == 3
    # By email: one client address asking for many strangers' addresses.
    api.headers.pop("Authorization")
    form = client.get("/reminders")
    token = re.search(r'name="csrf_token" value="([^"]+)"', form.text)
    assert token is not None
    statuses = [
        client.post(
            "/reminders", data={"csrf_token": token[1], "plate": "KTU 417 XA", "email": f"p{n}@example.ng"}
        ).status_code
        for n in range(22)
    ]
    assert statuses[:20] == [200] * 20
    assert statuses[20:] == [429, 429]


def test_checks_are_limited_per_phone(
    api: TestClient, client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    from app import config

    monkeypatch.setenv("TRIKECERT_CHECKS_PER_PHONE", "2")
    config.get_settings.cache_clear()
    certify(api, weigh(api, "KTU 417 XA"))
    assert "VALID CERTIFICATE" in _ussd(client, "1*KTU417XA")
    assert "VALID CERTIFICATE" in _ussd(client, "1*KTU417XA")
    assert _ussd(client, "1*KTU417XA") == "END Too many checks from this phone: try again in an hour."
    assert "VALID CERTIFICATE" in _ussd(client, "1*KTU417XA", phone="+2348099999999")


def test_the_reminders_form_refuses_bad_input_by_field_and_a_missing_csrf_token(
    api: TestClient, client: TestClient, session: Session
) -> None:
    weigh(api, "KTU 417 XA")
    api.headers.pop("Authorization")
    assert client.post("/reminders", data={"plate": "KTU 417 XA", "email": "a@example.ng"}).status_code == 403
    form = client.get("/reminders")
    token = re.search(r'name="csrf_token" value="([^"]+)"', form.text)
    assert token is not None
    for data, field, words in [
        ({"plate": "", "email": "a@example.ng"}, "plate", "Enter the plate"),
        ({"plate": "ZZZ 9", "email": "a@example.ng"}, "plate", "No keke ZZZ 9 is registered"),
        ({"plate": "KTU 417 XA", "email": "nope"}, "email", "Enter an email address like name@example.com"),
        ({"plate": "KTU 417 XA", "email": "x" * 10_000}, "email", ""),
        ({"plate": "KTU\u202e417", "email": "a@example.ng"}, "plate", ""),
    ]:
        refused = client.post("/reminders", data={"csrf_token": token[1], **data})
        assert refused.status_code == 422, (data, refused.text[:300])
        assert f'href="#{field}"' in refused.text
        assert words in refused.text
    assert session.scalars(select(Subscription)).all() == []


def test_admins_see_counts_and_never_a_contact(api: TestClient, client: TestClient, session: Session) -> None:
    from app.accounts.service import create_user

    certify(api, weigh(api, "KTU 417 XA"))
    _ussd(client, "2*KTU417XA")
    create_user(
        session,
        email="admin@example.gov",
        password="correct horse battery staple",
        role="admin",
        name="Ada Admin",
    )
    api.headers.pop("Authorization")
    form = client.get("/login")
    token = re.search(r'name="csrf_token" value="([^"]+)"', form.text)
    assert token is not None
    signed = client.post(
        "/login",
        data={
            "csrf_token": token[1],
            "email": "admin@example.gov",
            "password": "correct horse battery staple",
            "next": "/admin/reminders",
        },
    )
    assert signed.status_code in (200, 303)
    page = client.get("/admin/reminders")
    assert page.status_code == 200, page.text[:300]
    assert 'id="pending">1<' in page.text
    assert "8012345667" not in page.text
    assert "•" not in page.text
