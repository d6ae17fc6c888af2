"""The digests kept of phone numbers and email addresses cannot be reversed by hashing every number:
they are keyed with a secret that is never in the database."""

from __future__ import annotations

import hashlib
import hmac
import stat

import pytest
from fastapi.testclient import TestClient
from pydantic import ValidationError
from sqlalchemy import select
from sqlalchemy.orm import Session

from app import config
from app.notifications.contacts import digest
from app.notifications.digest_key import digest_key_path
from app.notifications.models import GatewayCheck, Subscription
from notifications.phone_helpers import PHONE, USSD, certify, weigh

pytestmark = pytest.mark.usefixtures("gateway_on")


def _ussd(client: TestClient, text: str) -> str:
    response = client.post(
        USSD, data={"sessionId": "s1", "serviceCode": "*384#", "phoneNumber": PHONE, "text": text}
    )
    assert response.status_code == 200
    return response.text


def _keyed(key: bytes, value: str) -> str:
    return hmac.new(key, f"trikecert-contact:{value}".encode(), hashlib.sha256).hexdigest()


def test_a_phones_kept_digests_are_keyed_with_a_secret_file_beside_the_signing_key(
    api: TestClient, client: TestClient, session: Session
) -> None:
    certify(api, weigh(api, "KTU 417 XA"))
    assert "VALID CERTIFICATE" in _ussd(client, "1*KTU417XA")
    assert _ussd(client, "2*KTU417XA").startswith("END A code was sent")

    kept = {check.phone_digest for check in session.scalars(select(GatewayCheck))}
    kept |= {subscription.contact_digest for subscription in session.scalars(select(Subscription))}
    assert len(kept) == 1  # one phone: the limits still see its requests as one contact's
    # What anyone reading the database could compute for every number: not what is kept.
    assert kept.isdisjoint(
        {
            hashlib.sha256(f"trikecert-contact:{PHONE}".encode()).hexdigest(),
            hashlib.sha256(PHONE.encode()).hexdigest(),
        }
    )
    key_file = digest_key_path(config.get_settings())
    assert key_file.parent == config.get_settings().signing_key_file.parent  # type: ignore[union-attr]
    assert stat.S_IMODE(key_file.stat().st_mode) == 0o600
    assert kept == {_keyed(key_file.read_text().strip().encode(), PHONE)}


def test_the_digest_key_setting_replaces_the_file_and_changes_every_digest(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from_file = digest(PHONE)
    monkeypatch.setenv("TRIKECERT_CONTACT_DIGEST_KEY", "k" * 40)
    config.get_settings.cache_clear()
    try:
        assert digest(PHONE) == digest(PHONE) == _keyed(b"k" * 40, PHONE)
        assert digest(PHONE) != from_file
        assert digest("+2348099999999") != digest(PHONE)
    finally:
        monkeypatch.delenv("TRIKECERT_CONTACT_DIGEST_KEY")
        config.get_settings.cache_clear()


def test_a_short_digest_key_is_refused_naming_the_setting() -> None:
    with pytest.raises(ValidationError, match="contact_digest_key"):
        config.Settings(contact_digest_key="too-short")
