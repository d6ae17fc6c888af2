"""A keke checked from a feature phone: a USSD session and an SMS, posted exactly as Africa's Talking
posts them, for every state a document can be in; each reply within one screen or one SMS."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.notifications.models import OutboxMessage
from app.notifications.sms_text import USSD_SCREEN, fits_sms, sms_units
from notifications.phone_helpers import PHONE, SMS, TOKEN, USSD, State

pytestmark = pytest.mark.usefixtures("gateway_on")


def ussd(client: TestClient, text: str, session_id: str = "ATUid_1", phone: str = PHONE) -> str:
    """One USSD step as the gateway posts it; the plain-text answer."""
    response = client.post(
        USSD, data={"sessionId": session_id, "serviceCode": "*384*123#", "phoneNumber": phone, "text": text}
    )
    assert response.status_code == 200, response.text
    assert response.headers["content-type"].startswith("text/plain")
    assert response.text.startswith(("CON ", "END "))
    assert len(response.text) <= USSD_SCREEN
    return response.text


def sms(client: TestClient, text: str, message_id: str, phone: str = PHONE) -> int:
    """An incoming SMS as the gateway posts it; the status."""
    response = client.post(
        SMS,
        data={
            "from": phone,
            "to": "12345",
            "text": text,
            "date": "2026-12-03 18:00:00",
            "id": message_id,
            "linkId": "SampleLinkId123",
        },
    )
    return response.status_code


def replies(session: Session) -> list[str]:
    session.expire_all()
    rows = session.scalars(
        select(OutboxMessage).where(OutboxMessage.purpose == "reply").order_by(OutboxMessage.id)
    )
    return [row.body for row in rows]


def test_a_ussd_session_checks_each_state_in_the_verify_pages_words(
    client: TestClient, states: list[State]
) -> None:
    for number, state in enumerate(states):
        session_id = f"ATUid_{number}"
        menu = ussd(client, "", session_id)
        assert menu == (
            "CON Keke check\n1. Check a keke\n2. Remind me before it expires\n3. Stop reminders\n"
            "4. Language/Harshe/Ede/Asusu"
        )
        assert ussd(client, "1", session_id) == "CON Enter the plate or certificate number"
        answer = ussd(client, f"1*{state.query}", session_id)
        assert answer.startswith("END "), state.name
        for words in state.words:
            assert words in answer, (state.name, answer)


def test_an_sms_check_replies_once_within_one_sms_for_each_state(
    client: TestClient, session: Session, states: list[State]
) -> None:
    for number, state in enumerate(states):
        text = f"CHECK {state.query}" if number % 2 else state.query
        assert sms(client, text, f"ATXid_{number}") == 200
        body = replies(session)[-1]
        assert fits_sms(body), (state.name, body, sms_units(body))
        assert len(body) <= 160
        for words in state.words:
            assert words in body, (state.name, body)
    assert len(replies(session)) == len(states)


def test_a_replayed_sms_callback_is_answered_once(
    client: TestClient, session: Session, states: list[State]
) -> None:
    assert sms(client, "CHECK KTU 417 XA", "ATXid_replayed") == 200
    assert sms(client, "CHECK KTU 417 XA", "ATXid_replayed") == 200
    assert len(replies(session)) == 1


def test_callbacks_without_the_token_are_404_and_counted(client: TestClient) -> None:
    def refused_count() -> float:
        metrics = client.get("/metrics").text
        lines = [
            line
            for line in metrics.splitlines()
            if line.startswith('trikecert_gateway_callbacks_refused_total{reason="token"}')
        ]
        return float(lines[0].split()[-1]) if lines else 0.0

    before = refused_count()
    form = {"sessionId": "s", "serviceCode": "*384#", "phoneNumber": PHONE, "text": ""}
    assert client.post("/gateway/africastalking/ussd", data=form).status_code == 404
    assert client.post("/gateway/africastalking/ussd?token=wrong", data=form).status_code == 404
    assert client.post("/gateway/africastalking/sms?token=wrong", data={"from": PHONE}).status_code == 404
    assert refused_count() == before + 3


def test_callbacks_are_off_without_a_token_setting(
    client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    from app import config

    monkeypatch.delenv("TRIKECERT_GATEWAY_CALLBACK_TOKEN")
    config.get_settings.cache_clear()
    form = {"sessionId": "s", "serviceCode": "*384#", "phoneNumber": PHONE, "text": ""}
    assert client.post(USSD, data=form).status_code == 404
    monkeypatch.setenv("TRIKECERT_GATEWAY_CALLBACK_TOKEN", TOKEN)
    config.get_settings.cache_clear()


def test_callbacks_only_from_the_configured_addresses(
    client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    from app import config

    form = {"sessionId": "s", "serviceCode": "*384#", "phoneNumber": PHONE, "text": ""}
    monkeypatch.setenv("TRIKECERT_GATEWAY_ALLOWED_IPS", "192.0.2.0/24")
    config.get_settings.cache_clear()
    assert client.post(USSD, data=form).status_code == 404  # the test client is "testclient"
    monkeypatch.delenv("TRIKECERT_GATEWAY_ALLOWED_IPS")
    config.get_settings.cache_clear()
    assert client.post(USSD, data=form).status_code == 200


SCRIPTS = [
    "КТУ 417 ХА",  # Cyrillic look-alikes
    "كيكي ٤١٧",  # Arabic with Arabic-Indic digits
    "ｋｔｕ４１７",  # full-width
    "🛺🛺🛺",
    "ẞ" * 50,
    "\u202eKTU417XA",  # a bidi override
    "KTU\x00417",
    "*" * 30,
    "1*" + "x" * 10_000,
]


@pytest.mark.parametrize("text", SCRIPTS)
def test_any_text_gets_a_well_formed_ussd_answer(client: TestClient, text: str) -> None:
    answer = ussd(client, text if text.startswith("1*") else f"1*{text}")
    assert answer.startswith("CON " if set(text) == {"*"} else "END ")


@pytest.mark.parametrize("text", SCRIPTS)
def test_any_text_by_sms_gets_a_reply_within_one_sms_or_a_4xx(
    client: TestClient, session: Session, text: str
) -> None:
    status = sms(client, text, f"ATXid_{abs(hash(text))}")
    assert status in (200, 422), status
    for body in replies(session):
        assert fits_sms(body), body


def test_ten_thousand_characters_and_missing_fields_are_4xx_or_answered(
    client: TestClient, session: Session
) -> None:
    assert client.post(USSD, data={"sessionId": "s"}).status_code == 422
    assert client.post(SMS, data={"from": PHONE, "text": "CHECK X"}).status_code == 422  # no id
    assert client.post(SMS, data={}).status_code == 422
    nul_id = {"from": PHONE, "to": "1", "text": "CHECK KTU417XA", "id": "ATXid\x00"}
    assert client.post(SMS, data=nul_id).status_code == 422  # PostgreSQL could not even store it
    assert (
        client.post(
            USSD, data={"sessionId": "s", "serviceCode": "*1#", "phoneNumber": "+234\x00", "text": "1*X"}
        ).status_code
        == 422
    )
    assert client.post(
        USSD, content=b"\xff\xfe garbage", headers={"content-type": "application/x-www-form-urlencoded"}
    ).status_code in (200, 400, 422)
    assert sms(client, "K" * 10_000, "ATXid_long") == 200
    assert all(fits_sms(body) for body in replies(session))
    assert (
        client.post(SMS, data={"from": PHONE, "to": "1", "text": "x" * 30_000, "id": "big"}).status_code
        == 422
    )


def test_unknown_menu_choices_end_the_session_politely(client: TestClient) -> None:
    assert ussd(client, "9").startswith("END Choose 1, 2 or 3.")
    assert ussd(client, "1*").startswith("CON ")
