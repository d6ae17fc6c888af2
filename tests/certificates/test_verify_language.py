"""What a machine reads of a paper does not depend on the reader's language: the JSON verification
(both addresses, with a genuine QR payload, a bad one or none) is byte-identical whatever the
Accept-Language or language cookie."""

from __future__ import annotations

from typing import Any
from urllib.parse import quote

import pytest
from certificate_helpers import register, study_certificate, weigh
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session
from web.webtools import OFFICER_EMAIL, PASSWORD, hidden, sign_in

import app.certificates.service as service
from app.accounts.service import create_user
from app.certificates.actors import Actor
from app.certificates.models import Certificate
from app.config import get_settings
from app.i18n.active import current_locale, use_locale
from app.trust.claims import Claims
from app.trust.cwt import verify_cwt
from app.trust.keys import published_keys
from app.trust.signing import sign_payload
from app.wording import occupancy_sentence, verdict_sentence

JSON = {"Accept": "application/json"}
LOCALES = ("ha", "yo", "ig", "pcm")


@pytest.fixture
def issued(api: TestClient) -> dict[str, Any]:
    body = study_certificate(api)
    api.headers.pop("Authorization")  # the verification is public
    return body


@pytest.mark.parametrize("address", ["/api/v1/verify", "/verify"])
def test_the_json_verification_is_the_same_in_every_language(
    issued: dict[str, Any], client: TestClient, address: str
) -> None:
    payload = quote(issued["qr_payload"], safe="")
    for query in ("", f"?p={payload}", "?p=not-a-payload"):
        url = f"{address}/{issued['number']}{query}"
        english = client.get(url, headers=JSON)
        assert english.status_code == 200
        for locale in LOCALES:
            by_header = client.get(url, headers={**JSON, "Accept-Language": locale})
            by_cookie = client.get(url, headers={**JSON, "Cookie": f"trikecert_lang={locale}"})
            assert by_header.content == english.content, (url, locale)
            assert by_cookie.content == english.content, (url, locale)


def test_a_paper_issued_from_a_hausa_page_signs_the_same_claims_as_in_english(
    api: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The officer's page language reaches neither the signed claims (the QR payload) nor the frozen facts."""
    register(api)
    inspection_id = weigh(api)
    signed: list[tuple[str, Claims]] = []
    real_sign = sign_payload

    def spy(claims: Claims, **kwargs: Any) -> str:
        signed.append((current_locale(), claims))
        return real_sign(claims, **kwargs)

    class Stop(Exception):
        pass

    def stop(document: Any) -> bytes:
        raise Stop

    monkeypatch.setattr(service, "sign_payload", spy)
    # In English first, stopped before the paper is drawn and rolled back: the number goes back.
    monkeypatch.setattr(service, "render_pdf", stop)
    with pytest.raises(Stop):
        service.issue_certificate(
            session, inspection_id=inspection_id, actor=Actor.of_cli(), settings=get_settings()
        )
    session.rollback()
    monkeypatch.undo()
    monkeypatch.setattr(service, "sign_payload", spy)

    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    api.cookies.set("trikecert_lang", "ha")
    hausa = {"Accept-Language": "ha"}
    page = api.get(f"/inspections/{inspection_id}", headers=hausa)
    assert page.status_code == 200
    assert '<html lang="ha">' in page.text
    issued = api.post(
        f"/inspections/{inspection_id}/certificate",
        data={"csrf_token": hidden(page.text)},
        headers=hausa,
        follow_redirects=False,
    )
    assert issued.status_code == 303, issued.text
    number = issued.headers["location"].rsplit("/", 1)[1]

    (english_locale, english), (page_locale, from_page) = signed
    assert (english_locale, page_locale) == ("en", "ha")  # the page really was Hausa
    assert from_page == english
    assert (from_page.kind, from_page.issuer) == (english.kind, english.issuer)
    assert from_page.number == number

    # The QR payload on record reads back as exactly those claims.
    stored = session.scalars(select(Certificate).where(Certificate.number == number)).one()
    read = verify_cwt(stored.qr_payload, published_keys(session, get_settings()))
    assert read.claims == english
    # The facts frozen with the paper are in English, the binding text.
    with use_locale("en"):
        assert stored.facts["verdict"] == verdict_sentence(
            [(c["occupants"], c["compliant"]) for c in stored.facts["cases"]],
            stored.facts["max_compliant_occupants"],
        )
        assert stored.facts["occupancy"] == occupancy_sentence(
            stored.facts["compliant"], stored.facts["max_compliant_occupants"]
        )
    assert stored.facts["verdict"].startswith(("Compliant.", "Not compliant."))
