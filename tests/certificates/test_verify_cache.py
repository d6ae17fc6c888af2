"""The public verification's kept answers (app/certificates/answer_cache.py) are never stale: a
revocation, a supersession and an expiry by the clock show on the very next request after the answer
was kept; an answer in one language is never served in another, and one number's never for another's."""

from __future__ import annotations

from datetime import timedelta
from typing import Any

import pytest
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, weigh
from fastapi.testclient import TestClient
from sqlalchemy.exc import OperationalError
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

    def counted(kind: str, asked: str, make: Any) -> Any:
        def counted_make() -> Any:
            made.append(asked)
            return make()

        return keep(kind, asked, counted_make)

    monkeypatch.setattr("app.certificates.verify_json.kept_answer", counted)
    written_otherwise = number.lower()
    assert api.get(f"/api/v1/verify/{written_otherwise}").json() == first
    assert made == []  # another way of writing the number is served the answer kept for it
    second = api.get(f"/api/v1/verify/{other}").json()
    assert made == [other]
    assert (first["number"], second["number"]) == (number, other)
    assert api.get(f"/api/v1/verify/{number}").json()["number"] == number


DOORS = {  # the three addresses of a public verification: path prefix, request headers
    "page": ("/verify/", {}),
    "page as JSON": ("/verify/", JSON),
    "API": ("/api/v1/verify/", {}),
}
PER_REQUEST = {"date", "x-request-id"}


def comparable(response: Any) -> tuple[int, bytes, list[tuple[str, str]]]:
    """Status, body and headers in order, without those made anew for every request."""
    headers = [(name, value) for name, value in response.headers.multi_items() if name not in PER_REQUEST]
    return response.status_code, response.content, headers


@pytest.mark.parametrize("door", DOORS)
def test_a_kept_answer_is_served_before_the_router_exactly_as_the_route_sent_it(
    door: str, certificate: dict[str, Any], client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    prefix, headers = DOORS[door]
    address = prefix + certificate["number"]
    made = client.get(address, headers=headers)  # made by the route, and kept

    def no_route(*_: Any, **__: Any) -> Any:
        raise AssertionError("the route was called for a kept answer")

    monkeypatch.setattr("app.certificates.views.kept_answer", no_route)
    monkeypatch.setattr("app.certificates.verify_json.kept_answer", no_route)
    served = client.get(address, headers=headers)
    assert comparable(served) == comparable(made)
    assert served.headers["x-request-id"] != made.headers["x-request-id"]


@pytest.mark.parametrize("door", DOORS)
def test_a_revocation_shows_on_the_next_request_at_each_door(
    door: str, certificate: dict[str, Any], client: TestClient, session: Session
) -> None:
    prefix, headers = DOORS[door]
    address = prefix + certificate["number"]
    for _ in range(3):
        assert "revoked" not in client.get(address, headers=headers).text.lower()
    revoke_certificate(session, number=certificate["number"], actor=Actor.of_cli(), reason="Stolen plate")
    session.commit()
    answer = client.get(address, headers=headers)
    assert answer.status_code == 200
    assert ("REVOKED" in answer.text) if door == "page" else answer.json()["status"] == "revoked"


def test_a_scanned_payload_or_any_query_goes_to_the_route(
    certificate: dict[str, Any], client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    number = certificate["number"]
    warm(client, number)
    called: list[str] = []
    route = answer_cache.kept_answer

    def counted(kind: str, asked: str, make: Any) -> Any:
        called.append(kind)
        return route(kind, asked, make)

    monkeypatch.setattr("app.certificates.views.kept_answer", counted)
    monkeypatch.setattr("app.certificates.verify_json.kept_answer", counted)
    client.get(f"/verify/{number}")
    assert called == []
    assert client.get(f"/verify/{number}?p=NOT-A-PAYLOAD").status_code == 200  # the route checks it
    client.get(f"/verify/{number}?utm=poster")
    client.get(f"/api/v1/verify/{number}?utm=poster")
    assert called == ["verify-html", "api-verify"]


def test_a_database_that_fails_the_door_leaves_the_answer_to_the_route(
    certificate: dict[str, Any], client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    number = certificate["number"]
    warm(client, number)

    async def outage() -> object:
        raise OperationalError("SELECT max(id)", {}, Exception("connection refused"))

    monkeypatch.setattr(answer_cache.CHANGE_MARK, "read_soon", outage)
    assert statuses(client, number) == ("certified", "certified", "valid")


def test_the_request_log_names_the_route_that_kept_the_answer(
    certificate: dict[str, Any], client: TestClient
) -> None:
    number = certificate["number"]
    warm(client, number)
    metrics = client.get("/metrics").text
    served = [line for line in metrics.splitlines() if 'handler="verify_page"' in line and "_total" in line]
    assert served, "the kept answers are counted under the route's name"
    assert 'handler="unmatched"' not in "".join(served)
