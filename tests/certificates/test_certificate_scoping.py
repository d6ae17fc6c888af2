"""Certificates belong to their station: another station's certificate and PDF are 404, as inspections
are; the station API names who issued a document by role and name, never by email."""

from __future__ import annotations

from certificate_helpers import register, study_certificate, weigh
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.accounts.service import create_user
from app.certificates.actors import Actor
from app.certificates.service import issue_certificate
from app.config import get_settings
from app.stations.service import create_station


def test_another_station_gets_404_for_the_certificate_and_its_pdf(api: TestClient, session: Session) -> None:
    number = study_certificate(api)["number"]
    _other, other_key = create_station(session, name="Another weighbridge")
    other = {"Authorization": f"Bearer {other_key}"}
    for path in (f"/api/v1/certificates/{number}", f"/api/v1/certificates/{number}/pdf"):
        assert api.get(path).status_code == 200
        refused = api.get(path, headers=other)
        assert refused.status_code == 404
        assert refused.json()["errors"][0]["field"] == "number"
        assert number not in refused.text or "no certificate" in refused.text
    unknown = api.get("/api/v1/certificates/TRK-2026-000777-Q", headers=other).json()
    assert set(unknown) == set(api.get(f"/api/v1/certificates/{number}", headers=other).json())


def test_a_certificate_issued_by_an_officer_names_a_role_and_the_name_not_an_email(
    api: TestClient, session: Session
) -> None:
    register(api)
    inspection_id = weigh(api)
    officer = create_user(
        session,
        email="ada.officer@example.ng",
        password="a long pass phrase 1",
        role="officer",
        name="Ada Obi",
        badge="LAG-1234",
    )
    issued = issue_certificate(
        session, inspection_id=inspection_id, actor=Actor.of_user(officer), settings=get_settings()
    )
    answer = api.get(f"/api/v1/certificates/{issued.certificate.number}")
    assert answer.status_code == 200  # the station's inspection, though an officer issued it
    assert answer.json()["issued_by"] == {"role": "officer", "name": "Ada Obi (badge LAG-1234)"}
    assert "ada.officer" not in answer.text
    assert "@" not in answer.text
