"""The public JSON verification: /api/v1/verify/{number} and /verify/{number} with Accept JSON, no key;
only what the paper prints; a status a machine can trust (certified, refused, revoked, superseded,
expired: a refusal is never in force as a certificate); with ?p= whether a QR payload is genuine;
old JWS payloads still verify.

Issue 21 changed what these tests pin: `status` was `valid` for any document in force, a refusal
too; it is now `certified` or `refused`, with `in_force`; the QR check's `reason`/`reason_text` are
now `qr_reason`/`qr_reason_text`, and `reason` is a revocation's."""

from __future__ import annotations

import json
from datetime import datetime, timedelta
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
from sqlalchemy.orm import Session

from app.certificates.actors import Actor
from app.certificates.schemas import VerificationOut
from app.certificates.service import issue_certificate, revoke_certificate
from app.cli import main
from app.config import get_settings
from app.db import utcnow
from app.trust.numbers import CertificateNumber, is_valid_number
from app.trust.validity import local_date

JSON = {"Accept": "application/json"}
FIELDS = {
    "number",
    "kind",
    "status",
    "in_force",
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
    assert (body["kind"], body["status"], body["in_force"]) == ("refusal", "refused", False)
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
    assert (body["kind"], body["status"], body["in_force"], body["superseded_by"]) == (
        "certificate",
        "superseded",
        False,
        new["number"],
    )
    assert body["superseded_on"] == local_date(datetime.fromisoformat(new["issued_at"])).isoformat()
    assert "revoked_on" not in body
    fresh = client.get(f"/api/v1/verify/{new['number']}").json()
    assert (fresh["kind"], fresh["status"], fresh["in_force"]) == ("certificate", "certified", True)
    assert not {"superseded_by", "superseded_on", "revoked_on", "reason"} & set(fresh)


def test_a_revoked_document_says_when_and_why_and_is_never_certified(
    api: TestClient, client: TestClient, session: Session
) -> None:
    register(api, FRONT_HEAVY)
    certificate = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    revoked = revoke_certificate(
        session, number=certificate["number"], actor=Actor.of_cli(), reason="Wrong wheel readings"
    )
    assert revoked.revocation is not None
    payload = quote(certificate["qr_payload"], safe="")
    body = client.get(f"/api/v1/verify/{certificate['number']}?p={payload}").json()
    assert (body["kind"], body["status"], body["in_force"]) == ("certificate", "revoked", False)
    assert body["revoked_on"] == local_date(revoked.revocation.revoked_at).isoformat()
    assert body["reason"] == "Wrong wheel readings"
    assert (body["qr"], body["qr_reason"]) == ("genuine", "ok")  # genuine, and still not in force


def test_an_expired_document_is_expired_whatever_its_kind(
    api: TestClient, client: TestClient, session: Session
) -> None:
    register(api)
    long_ago = utcnow() - timedelta(days=400)
    issued = issue_certificate(
        session, inspection_id=weigh(api), actor=Actor.of_cli(), settings=get_settings(), now=long_ago
    )
    body = client.get(f"/api/v1/verify/{issued.certificate.number}").json()
    assert (body["kind"], body["status"], body["in_force"]) == ("refusal", "expired", False)
    assert body["valid_until"] == local_date(issued.certificate.expires_at).isoformat()


def test_the_qr_payload_is_genuine_and_a_flipped_one_is_not(
    issued: dict[str, Any], client: TestClient
) -> None:
    number, payload = issued["number"], issued["qr_payload"]
    genuine = client.get(f"/api/v1/verify/{number}?p={quote(payload, safe='')}").json()
    assert (genuine["qr"], genuine["qr_reason"]) == ("genuine", "ok")
    assert "reason" not in genuine  # `reason` is a revocation's, never the QR check's
    plus_kept = payload.replace("%", "%25").replace(" ", "%20")
    raw = client.get(f"/verify/{number}?p={plus_kept}", headers=JSON).json()
    assert raw["qr"] == "genuine"  # a '+' sent as itself stays a '+'
    flipped = payload[:30] + ("A" if payload[30] != "A" else "B") + payload[31:]
    forged = client.get(f"/api/v1/verify/{number}", params={"p": flipped}).json()
    assert forged["qr"] == "not_genuine"
    assert forged["qr_reason"] in ("bad_signature", "malformed", "tampered")
    assert forged["qr_reason_text"]
    assert forged["status"] == "refused"  # the record's status, whatever the scanned code says


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
    unknown = str(CertificateNumber(2026, 777))
    for path, rule in (
        ("/api/v1/verify/TRK-2026-000777-Q", "check_letter"),
        ("/verify/nonsense", "format"),
        (f"/api/v1/verify/{unknown}", "exists"),
        (f"/verify/{unknown}", "exists"),
    ):
        answer = client.get(path, headers=JSON)
        assert answer.status_code == 404
        problem = answer.json()["errors"][0]
        assert (problem["field"], problem["rule"]) == ("number", rule)
    assert answer.json()["detail"] == (
        f"number: no certificate or refusal {unknown} is on record: "
        "a paper that shows this number is not valid"
    )


def test_the_verification_is_in_the_openapi_schema_with_its_model(client: TestClient) -> None:
    schema = client.get("/openapi.json").json()
    operation = schema["paths"]["/api/v1/verify/{number}"]["get"]
    assert operation["responses"]["200"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/VerificationOut"
    }
    assert "security" not in operation
    model = schema["components"]["schemas"]["VerificationOut"]
    assert set(model["properties"]) >= FIELDS | {"qr", "qr_reason", "revoked_on", "reason", "superseded_by"}
    assert model["properties"]["status"]["enum"] == [
        "certified",
        "refused",
        "revoked",
        "superseded",
        "expired",
    ]
    assert "valid" not in json.dumps(model["properties"]["status"]["enum"])
    examples = operation["responses"]["200"]["content"]["application/json"]["examples"]
    assert {"certified", "refused", "revoked", "superseded", "expired"} <= set(examples)
    for name, example in examples.items():
        VerificationOut.model_validate(example["value"])  # every example is a real answer's shape
        assert example["value"]["in_force"] == (example["value"]["status"] == "certified"), name
        assert is_valid_number(example["value"]["number"]), name


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
    assert '<p class="qr-check__title">The QR code is genuine, but this paper is a REFUSAL</p>' in page.text
    assert client.get(f"/api/v1/verify/{number}", params={"p": token}).json()["qr"] == "genuine"
    assert client.get(f"/verify/{number}", params={"p": token}, headers=JSON).json()["qr"] == "genuine"
    assert main(["verify", body["qr_url"]]) == 3  # genuine, but a refusal certifies nothing
    out = capsys.readouterr().out
    assert f"refusal {number} for BDG 252 QH" in out
    assert "status: refused (a refusal: the vehicle is NOT certified)" in out
    forged = token[:-3] + ("AAA" if not token.endswith("AAA") else "BBB")
    assert client.get(f"/api/v1/verify/{number}", params={"p": forged}).json()["qr"] == "not_genuine"
