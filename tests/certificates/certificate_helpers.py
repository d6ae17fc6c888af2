"""Shared steps of the certificate tests: register and weigh a vehicle through the station API."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.certificates import service
from app.trust.jws import sign_jws
from app.trust.keys import okp_key
from app.trust.signer import MemorySigner
from app.trust.signing import Claims

VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"
# A front-heavy trike of our own: every loading case complies.
FRONT_HEAVY: dict[str, Any] = {
    "registration_number": "KTU-417-XA",
    "make": "TVS",
    "model": "King",
    "model_year": 2021,
    "chassis_number": "MD6M14PA7L4F00123",
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
}
FRONT_HEAVY_READINGS: dict[str, Any] = {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80}


def register(api: TestClient, vehicle: dict[str, Any] = STUDY_VEHICLE) -> None:
    """Register a vehicle through the API."""
    response = api.post(VEHICLES, json=vehicle)
    assert response.status_code == 201, response.text


def weigh(
    api: TestClient, registration: str = "BDG 252 QH", readings: dict[str, Any] = STUDY_READINGS
) -> int:
    """Submit one weighing and return the inspection id."""
    response = api.post(INSPECTIONS, json={"registration_number": registration, "readings": readings})
    assert response.status_code == 201, response.text
    inspection_id: int = response.json()["id"]
    return inspection_id


def certify(api: TestClient, inspection_id: int, expected: int = 201) -> dict[str, Any]:
    """Ask for an inspection's certificate and return its JSON."""
    response = api.post(f"{INSPECTIONS}/{inspection_id}/certificate")
    assert response.status_code == expected, response.text
    body: dict[str, Any] = response.json()
    return body


def study_certificate(api: TestClient) -> dict[str, Any]:
    """The study's vehicle registered, weighed and certified (a refusal)."""
    register(api)
    return certify(api, weigh(api))


def sign_as_before(claims: Claims, *, kid: str, key: MemorySigner) -> str:
    """The payload as certificates were signed before the CWT: a JWS compact token (by the key file's
    key, which the tests hold in memory)."""
    return sign_jws(claims, kid=kid, key=okp_key(key.private))


def issue_as_before(monkeypatch: pytest.MonkeyPatch) -> None:
    """Make the service issue certificates exactly as it did before the CWT (JWS in a /verify?p= URL)."""
    monkeypatch.setattr(service, "sign_payload", sign_as_before)
