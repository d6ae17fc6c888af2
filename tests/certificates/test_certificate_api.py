"""A station certifies its inspections over the API: numbers, status, supersession, the PDF download."""

from __future__ import annotations

import re
from datetime import UTC, datetime
from urllib.parse import quote

import base45  # type: ignore[import-untyped]
import cbor2
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.stations.service import create_station
from app.trust.numbers import is_valid_number

NUMBER = re.compile(r"^TRK-\d{4}-\d{6}-[A-Z]$")


def test_the_study_vehicle_gets_a_refusal_that_must_not_carry_passengers(api: TestClient) -> None:
    body = study_certificate(api)
    assert NUMBER.match(body["number"])
    assert is_valid_number(body["number"])
    assert body["number"][:15] == f"TRK-{datetime.now(UTC).year}-000001"
    assert (body["kind"], body["status"], body["compliant"]) == ("refusal", "issued", False)
    assert body["max_occupancy"] == "This vehicle must not carry passengers"
    assert body["verdict"] == (
        "Not compliant. Laterally stable with the driver alone; "
        "unstable with the driver and one or more passengers."
    )
    assert body["registration_number"] == "BDG 252 QH"
    assert body["verify_url"] == f"http://127.0.0.1:8000/verify/{body['number']}"
    payload = body["qr_payload"]
    assert set(payload) <= set("0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ $%*+-./:")  # base45
    assert cbor2.loads(base45.b45decode(payload)).tag == 18  # COSE_Sign1
    assert body["qr_url"] == "HTTP://127.0.0.1:8000/V/" + quote(payload, safe="$*+-.:")
    assert body["issued_by"] == {"role": "station", "name": "Test weighbridge"}
    assert body["supersedes"] is None
    assert body["revocation"] is None
    assert api.get(f"/api/v1/certificates/{body['number']}").json() == body


def test_asking_again_answers_200_with_the_same_certificate(api: TestClient) -> None:
    first = study_certificate(api)
    again = certify(api, first["inspection_id"], expected=200)
    assert again == first


def test_the_number_is_found_however_it_is_written_and_a_wrong_check_letter_is_404(api: TestClient) -> None:
    number = study_certificate(api)["number"]
    assert api.get(f"/api/v1/certificates/{number.lower().replace('-', '')}").json()["number"] == number
    wrong = number[:-1] + ("A" if number[-1] != "A" else "B")
    response = api.get(f"/api/v1/certificates/{wrong}")
    assert response.status_code == 404
    assert response.json()["errors"][0]["field"] == "number"
    assert api.get("/api/v1/certificates/TRK-2026-999999-" + "A").status_code == 404


def test_a_new_inspection_supersedes_the_old_certificate_and_an_older_one_cannot_be_certified(
    api: TestClient,
) -> None:
    register(api, FRONT_HEAVY)
    old_inspection = weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS)
    new_inspection = weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS)
    old = certify(api, old_inspection)
    assert (old["kind"], old["max_occupancy"]) == (
        "compliant",
        "Certified for the driver and up to one passenger",
    )
    new = certify(api, new_inspection)
    assert new["supersedes"] == old["number"]
    again = api.get(f"/api/v1/certificates/{old['number']}").json()
    assert (again["status"], again["superseded_by"]) == ("superseded", new["number"])
    refused = api.post(f"/api/v1/inspections/{old_inspection}/certificate")
    assert refused.status_code == 409
    assert refused.json()["errors"][0]["rule"] == "newer_certified"


def test_the_station_api_says_what_each_paper_means_beside_the_records_state(api: TestClient) -> None:
    """A refusal's record is issued, but it certifies nothing: a machine reads document_status/in_force."""
    refusal = study_certificate(api)
    assert (refusal["status"], refusal["document_status"], refusal["in_force"]) == (
        "issued",
        "refused",
        False,
    )
    register(api, FRONT_HEAVY)
    old = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    assert (old["status"], old["document_status"], old["in_force"]) == ("issued", "certified", True)
    certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    again = api.get(f"/api/v1/certificates/{old['number']}").json()
    assert (again["status"], again["document_status"], again["in_force"]) == (
        "superseded",
        "superseded",
        False,
    )


def test_a_station_cannot_certify_another_stations_inspection(api: TestClient, session: Session) -> None:
    register(api)
    inspection_id = weigh(api)
    _station, other_key = create_station(session, name="Another weighbridge")
    response = api.post(
        f"/api/v1/inspections/{inspection_id}/certificate", headers={"Authorization": f"Bearer {other_key}"}
    )
    assert response.status_code == 404
    assert api.post("/api/v1/inspections/999999/certificate").status_code == 404


def test_certificates_need_a_station_key(client: TestClient) -> None:
    assert client.get("/api/v1/certificates/TRK-2026-000001-A").status_code == 401
    assert client.post("/api/v1/inspections/1/certificate").status_code == 401


def test_a_certificate_cannot_be_deleted_over_the_api(api: TestClient) -> None:
    number = study_certificate(api)["number"]
    for path in (f"/api/v1/certificates/{number}", f"/api/v1/certificates/{number}/pdf"):
        response = api.delete(path)
        assert response.status_code == 405
        assert "detail" in response.json()
    assert api.put(f"/api/v1/certificates/{number}", json={}).status_code == 405
    assert api.get(f"/api/v1/certificates/{number}").json()["status"] == "issued"


def test_the_pdf_is_the_same_bytes_every_time_with_an_etag_and_304(api: TestClient) -> None:
    body = study_certificate(api)
    url = f"/api/v1/certificates/{body['number']}/pdf"
    first = api.get(url)
    assert first.status_code == 200
    assert first.headers["content-type"] == "application/pdf"
    assert first.content.startswith(b"%PDF-")
    etag = first.headers["etag"]
    assert etag == f'"{body["pdf_sha256"]}"'
    second = api.get(url)
    assert second.content == first.content
    assert second.headers["etag"] == etag
    not_modified = api.get(url, headers={"If-None-Match": etag})
    assert not_modified.status_code == 304
    assert not_modified.content == b""
    assert not_modified.headers["etag"] == etag
    assert api.get(url, headers={"If-None-Match": f'W/{etag}, "other"'}).status_code == 304
    assert api.get(url, headers={"If-None-Match": '"something-else"'}).status_code == 200


def test_the_signing_keys_are_published_for_anyone(api: TestClient, client: TestClient) -> None:
    body = study_certificate(api)
    client.headers.pop("Authorization", None)
    keys = client.get("/.well-known/trikecert-keys.json")
    assert keys.status_code == 200
    published = keys.json()["keys"]
    assert [k["kid"] for k in published] == [body["key_id"]]
    assert {k: published[0][k] for k in ("kty", "crv", "alg", "use")} == {
        "kty": "OKP",
        "crv": "Ed25519",
        "alg": "Ed25519",
        "use": "sig",
    }
    assert "d" not in published[0]
