"""The public JSON verification: /api/v1/verify/{number} and /verify/{number} with Accept JSON, no key;
only what the paper prints; with ?p= whether a QR payload is genuine; old JWS payloads still verify."""

from __future__ import annotations

from typing import Any
from urllib.parse import quote

import pytest
from certificate_helpers import (
    FRONT_HEAVY,
    FRONT_HEAVY_READINGS,
    certify,
    issue_as_before,
    register,
    study_certificate,
    weigh,
)
from fastapi.testclient import TestClient

from app.cli import main

JSON = {"Accept": "application/json"}
FIELDS = {
    "number",
    "kind",
    "status",
    "registration_number",
    "max_compliant_occupants",
    "issued_on",
    "valid_until",
}


@pytest.fixture
def issued(api: TestClient) -> dict[str, Any]:
    body = study_certificate(api)
    api.headers.pop("Authorization")  # the verification is public
    return body


def test_both_addresses_answer_the_printed_facts_without_a_key(
    issued: dict[str, Any], client: TestClient
) -> None:
    number = issued["number"]
    api = client.get(f"/api/v1/verify/{number}")
    page = client.get(f"/verify/{number}", headers=JSON)
    assert api.status_code == page.status_code == 200
    assert page.headers["content-type"] == "application/json"
    assert api.json() == page.json()
    body = api.json()
    assert set(body) == FIELDS
    assert body["number"] == number
    assert (body["kind"], body["status"]) == ("refusal", "valid")
    assert (body["registration_number"], body["max_compliant_occupants"]) == ("BDG 252 QH", 1)
    assert body["issued_on"] < body["valid_until"]
    assert "issued_by" not in body
    assert "@" not in api.text
    assert client.get(f"/verify/{number}").headers["content-type"].startswith("text/html")


def test_a_superseded_certificate_names_its_successor(api: TestClient, client: TestClient) -> None:
    register(api, FRONT_HEAVY)
    old = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    new = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    api.headers.pop("Authorization")
    body = client.get(f"/api/v1/verify/{old['number']}").json()
    assert (body["kind"], body["status"], body["superseded_by"]) == (
        "certificate",
        "superseded",
        new["number"],
    )
    assert "superseded_by" not in client.get(f"/api/v1/verify/{new['number']}").json()


def test_the_qr_payload_is_genuine_and_a_flipped_one_is_not(
    issued: dict[str, Any], client: TestClient
) -> None:
    number, payload = issued["number"], issued["qr_payload"]
    genuine = client.get(f"/api/v1/verify/{number}?p={quote(payload, safe='')}").json()
    assert (genuine["qr"], genuine["reason"]) == ("genuine", "ok")
    plus_kept = payload.replace("%", "%25").replace(" ", "%20")
    raw = client.get(f"/verify/{number}?p={plus_kept}", headers=JSON).json()
    assert raw["qr"] == "genuine"  # a '+' sent as itself stays a '+'
    flipped = payload[:30] + ("A" if payload[30] != "A" else "B") + payload[31:]
    forged = client.get(f"/api/v1/verify/{number}", params={"p": flipped}).json()
    assert forged["qr"] == "not_genuine"
    assert forged["reason"] in ("bad_signature", "malformed", "tampered")
    assert forged["reason_text"]


def test_the_short_qr_url_leads_json_clients_to_the_verification(
    issued: dict[str, Any], client: TestClient
) -> None:
    path = issued["qr_url"].removeprefix("HTTP://127.0.0.1:8000")
    for short in (path, "/v/" + path.removeprefix("/V/")):
        answer = client.get(short, headers=JSON)
        assert answer.status_code == 200
        assert answer.json()["qr"] == "genuine"
    unreadable = client.get("/V/NOT%20A%20PAYLOAD", headers=JSON)
    assert unreadable.status_code == 422
    assert unreadable.json()["errors"][0]["field"] == "payload"
    page = client.get("/V/NOT%20A%20PAYLOAD")
    assert page.status_code == 422
    assert "Type the certificate number printed on the paper" in page.text


def test_unknown_and_mistyped_numbers_are_404_in_the_error_shape(client: TestClient, engine: object) -> None:
    for path in ("/api/v1/verify/TRK-2026-000777-Q", "/verify/nonsense"):
        answer = client.get(path, headers=JSON)
        assert answer.status_code == 404
        assert answer.json()["errors"][0]["field"] == "number"


def test_the_verification_is_in_the_openapi_schema_with_its_model(client: TestClient) -> None:
    schema = client.get("/openapi.json").json()
    operation = schema["paths"]["/api/v1/verify/{number}"]["get"]
    assert operation["responses"]["200"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/VerificationOut"
    }
    assert "security" not in operation
    assert set(schema["components"]["schemas"]["VerificationOut"]["properties"]) >= FIELDS | {"qr", "reason"}


def test_a_payload_issued_before_the_cwt_still_verifies_everywhere(
    api: TestClient, client: TestClient, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    issue_as_before(monkeypatch)
    body = study_certificate(api)
    token, number = body["qr_payload"], body["number"]
    assert token.count(".") == 2  # a JWS, as issued before
    assert body["qr_url"] == f"http://127.0.0.1:8000/verify/{number}?p={token}"
    api.headers.pop("Authorization")
    page = client.get(body["qr_url"].removeprefix("http://127.0.0.1:8000"))
    assert '<p class="qr-check__title">The QR code is genuine</p>' in page.text
    assert client.get(f"/api/v1/verify/{number}", params={"p": token}).json()["qr"] == "genuine"
    assert client.get(f"/verify/{number}", params={"p": token}, headers=JSON).json()["qr"] == "genuine"
    assert main(["verify", body["qr_url"]]) == 0
    assert f"refusal {number} for BDG 252 QH" in capsys.readouterr().out
    forged = token[:-3] + ("AAA" if not token.endswith("AAA") else "BBB")
    assert client.get(f"/api/v1/verify/{number}", params={"p": forged}).json()["qr"] == "not_genuine"
