"""The public verification's kept answers (app/certificates/answer_cache.py) are never stale: a
revocation, a supersession and an expiry by the clock show on the very next request after the answer
was kept; an answer in one language is never served in another, and one number's never for another's."""

from __future__ import annotations

from datetime import timedelta
from typing import Any

import pytest
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, weigh
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from web.webtools import ADMIN_EMAIL, PASSWORD, hidden, sign_in

from app.accounts.service import create_user
from app.certificates import answer_cache, records
from app.certificates.actors import Actor
from app.certificates.service import reissue_certificate, revoke_certificate
from app.config import get_settings

JSON = {"Accept": "application/json"}


@pytest.fixture
def certificate(api: TestClient) -> dict[str, Any]:
    register(api, FRONT_HEAVY)
    return certify(api, weigh(api, FRONT_HEAVY["registration_number"], FRONT_HEAVY_READINGS))


def statuses(client: TestClient, number: str) -> tuple[str, str, str]:
    """The JSON status by both addresses, and the HTML banner's tone."""
    api = client.get(f"/api/v1/verify/{number}").json()["status"]
    page_json = client.get(f"/verify/{number}", headers=JSON).json()["status"]
    page = client.get(f"/verify/{number}").text
    tone = page.split('class="status status--', 1)[1].split('"', 1)[0]
    return api, page_json, tone


def warm(client: TestClient, number: str) -> None:
    for _ in range(2):  # the second answer is the kept one
        assert statuses(client, number) == ("certified", "certified", "valid")


def test_a_revocation_shows_on_the_very_next_request(
    certificate: dict[str, Any], client: TestClient, session: Session
) -> None:
    number = certificate["number"]
    warm(client, number)
    revoke_certificate(session, number=number, actor=Actor.of_cli(), reason="Plate does not match")
    session.commit()
    assert statuses(client, number) == ("revoked", "revoked", "revoked")


def test_a_revocation_on_the_officer_page_shows_on_the_very_next_request(
    certificate: dict[str, Any], api: TestClient, session: Session
) -> None:
    number = certificate["number"]
    api.headers.pop("Authorization")
    warm(api, number)
    create_user(session, email=ADMIN_EMAIL, password=PASSWORD, role="admin")
    assert sign_in(api, ADMIN_EMAIL).status_code == 303
    token = hidden(api.get("/").text)
    done = api.post(f"/certificates/{number}/revoke", data={"csrf_token": token, "reason": "Forged ticket"})
    assert done.status_code == 200
    api.cookies.clear()  # the public, not signed in
    assert statuses(api, number) == ("revoked", "revoked", "revoked")


def test_a_supersession_shows_on_the_very_next_request(
    certificate: dict[str, Any], client: TestClient, session: Session
) -> None:
    number = certificate["number"]
    warm(client, number)
    newer = reissue_certificate(
        session, number=number, actor=Actor.of_cli(), reason="lost", settings=get_settings()
    )
    session.commit()
    assert statuses(client, number) == ("superseded", "superseded", "lapsed")
    assert statuses(client, newer.number) == ("certified", "certified", "valid")


def test_an_expiry_by_the_clock_shows_on_the_very_next_request(
    certificate: dict[str, Any], client: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    number = certificate["number"]
    warm(client, number)
    found = records.find_certificate(session, number)
    assert found is not None
    later = found.expires_at + timedelta(seconds=1)
    for clock in (records, answer_cache):  # nothing was written: only the clock moved on
        monkeypatch.setattr(clock, "utcnow", lambda: later)
    assert statuses(client, number) == ("expired", "expired", "lapsed")


def test_an_answer_is_kept_per_language(certificate: dict[str, Any], client: TestClient) -> None:
    number = certificate["number"]
    english = client.get(f"/verify/{number}")
    kept = client.get(f"/verify/{number}")
    assert kept.text == english.text
    assert kept.headers.get("vary") == english.headers.get("vary")
    assert '<html lang="en-GB"' in english.text
    assert '<html lang="ha"' in client.get(f"/verify/{number}", headers={"Accept-Language": "ha"}).text
    client.cookies.set("trikecert_lang", "ha")
    assert '<html lang="ha"' in client.get(f"/verify/{number}").text
    client.cookies.clear()
    assert '<html lang="en-GB"' in client.get(f"/verify/{number}").text


def test_an_answer_is_kept_per_number(
    certificate: dict[str, Any], api: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    number = certificate["number"]
    other = certify(api, weigh(api, FRONT_HEAVY["registration_number"], FRONT_HEAVY_READINGS))["number"]
    api.headers.pop("Authorization")
    first = api.get(f"/api/v1/verify/{number}").json()
    made: list[str] = []
    keep = answer_cache.kept_answer

    def counted(session: Session, kind: str, asked: str, make: Any) -> Any:
        def counted_make() -> Any:
            made.append(asked)
            return make()

        return keep(session, kind, asked, counted_make)

    monkeypatch.setattr("app.certificates.verify_json.kept_answer", counted)
    written_otherwise = number.lower()
    assert api.get(f"/api/v1/verify/{written_otherwise}").json() == first
    assert made == []  # another way of writing the number is served the answer kept for it
    second = api.get(f"/api/v1/verify/{other}").json()
    assert made == [other]
    assert (first["number"], second["number"]) == (number, other)
    assert api.get(f"/api/v1/verify/{number}").json()["number"] == number
