"""A station sees only its own inspections: station B cannot read station A's (404, exactly as for one
that does not exist) and its list holds only its own; officers' inspections are not in any station's."""

from __future__ import annotations

from decimal import Decimal
from typing import Any

from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from station_server import seed_study_vehicle

from app.inspections.service import InspectionRequest, record_inspection
from app.stability import Rules, WheelReadings
from app.stations.service import create_station

INSPECTIONS = "/api/v1/inspections"
STUDY: dict[str, Any] = {
    "registration_number": "BDG 252 QH",
    "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
}


def as_station(client: TestClient, key: str) -> dict[str, str]:
    return {"Authorization": f"Bearer {key}"}


def test_station_b_cannot_read_station_as_inspection(client: TestClient, session: Session) -> None:
    _a, key_a = create_station(session, name="Station A")
    _b, key_b = create_station(session, name="Station B")
    seed_study_vehicle(session)
    created = client.post(INSPECTIONS, json=STUDY, headers=as_station(client, key_a))
    assert created.status_code == 201
    inspection_id = created.json()["id"]

    by_a = client.get(f"{INSPECTIONS}/{inspection_id}", headers=as_station(client, key_a))
    by_b = client.get(f"{INSPECTIONS}/{inspection_id}", headers=as_station(client, key_b))
    missing = client.get(f"{INSPECTIONS}/{inspection_id + 1000}", headers=as_station(client, key_b))

    assert by_a.status_code == 200
    assert by_a.json()["station"] == "Station A"
    assert by_b.status_code == 404
    assert by_b.json()["errors"][0]["rule"] == "exists"
    assert by_b.json()["detail"] == f"inspection_id: inspection {inspection_id} does not exist"
    assert (
        missing.json()["detail"].replace(str(inspection_id + 1000), str(inspection_id))
        == by_b.json()["detail"]
    )


def test_each_station_lists_only_its_own_inspections(client: TestClient, session: Session) -> None:
    _a, key_a = create_station(session, name="Station A")
    _b, key_b = create_station(session, name="Station B")
    seed_study_vehicle(session)
    for key in (key_a, key_a, key_b):
        assert client.post(INSPECTIONS, json=STUDY, headers=as_station(client, key)).status_code == 201
    record_inspection(  # an officer's weighing, through the pages
        session,
        request=InspectionRequest(
            registration_number="BDG 252 QH",
            readings=WheelReadings((Decimal(108),), (Decimal(115),), (Decimal(135),)),
        ),
        rules=Rules(),
    )

    page_a = client.get(INSPECTIONS, headers=as_station(client, key_a)).json()
    page_b = client.get(
        INSPECTIONS, params={"registration_number": "bdg252qh"}, headers=as_station(client, key_b)
    ).json()

    assert page_a["total"] == 2
    assert {i["station"] for i in page_a["items"]} == {"Station A"}
    assert page_b["total"] == 1
    assert page_b["items"][0]["station"] == "Station B"
