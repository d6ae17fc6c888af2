"""Shared steps of the feature-phone tests: the gateway's addresses, vehicles weighed and certified."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from fastapi.testclient import TestClient
from study_data import STUDY_READINGS, STUDY_VEHICLE

TOKEN = "callback-secret-0123456789"
USSD = f"/gateway/africastalking/ussd?token={TOKEN}"
SMS = f"/gateway/africastalking/sms?token={TOKEN}"
PHONE = "+2348012345667"


def trike(plate: str, *, stable: bool = True) -> dict[str, Any]:
    """A vehicle to register: front-heavy (every case complies) or the study's (a refusal)."""
    if not stable:
        return {**STUDY_VEHICLE, "registration_number": plate}
    return {
        "registration_number": plate,
        "make": "TVS",
        "model": "King",
        "model_year": 2021,
        "wheelbase_m": 2.0,
        "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
    }


STABLE_READINGS = {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80}


def weigh(api: TestClient, plate: str, *, stable: bool = True, register: bool = True) -> int:
    """Register (once) and weigh a vehicle through the station API; the inspection's id."""
    if register:
        response = api.post("/api/v1/vehicles", json=trike(plate, stable=stable))
        assert response.status_code == 201, response.text
    readings = STABLE_READINGS if stable else STUDY_READINGS
    weighed = api.post("/api/v1/inspections", json={"registration_number": plate, "readings": readings})
    assert weighed.status_code == 201, weighed.text
    inspection_id: int = weighed.json()["id"]
    return inspection_id


def certify(api: TestClient, inspection_id: int) -> str:
    """Issue the inspection's document; its number."""
    response = api.post(f"/api/v1/inspections/{inspection_id}/certificate")
    assert response.status_code == 201, response.text
    number: str = response.json()["number"]
    return number


@dataclass(frozen=True)
class State:
    """A document state, what a phone sends to ask about it, and words the answer must hold."""

    name: str
    query: str
    words: tuple[str, ...]
