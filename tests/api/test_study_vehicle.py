"""The study's vehicle through the station API: register it, weigh it, read Table 4 back."""

from __future__ import annotations

from fastapi.testclient import TestClient
from study_data import STUDY_READINGS, STUDY_VEHICLE


def test_the_study_vehicle_gets_table_4_with_c_only_for_the_driver_alone(api: TestClient) -> None:
    assert api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    response = api.post(
        "/api/v1/inspections", json={"registration_number": "bdg-252qh", "readings": STUDY_READINGS}
    )
    assert response.status_code == 201, response.text
    body = response.json()
    rows = [
        (c["occupants"], c["total_kg"], c["rear_kg"], c["lsf"], c["variance"], c["compliant"])
        for c in body["loading_cases"]
    ]
    assert rows == [
        (0, 359.0, 250.0, 0.6964, -0.0297, False),
        (1, 431.0, 283.49, 0.6578, 0.0089, True),
        (2, 503.0, 342.18, 0.6803, -0.0136, False),
        (3, 575.0, 400.87, 0.6972, -0.0305, False),
        (4, 647.0, 459.56, 0.7103, -0.0436, False),
    ]
    assert body["compliant"] is False
    assert body["max_compliant_occupants"] == 1
    assert body["cg_from_front_m"] == 1.3928
    assert body["readings"]["total_kg"] == 359.0

    stored = api.get(f"/api/v1/inspections/{body['id']}")
    assert stored.status_code == 200
    assert stored.json() == body
