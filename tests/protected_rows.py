"""A row in every append-only table, made the way the service makes them (shared by the tests of the
database's own refusals: triggers and grants)."""

from __future__ import annotations

from typing import Any

from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_TYPE_READINGS, STUDY_VEHICLE

from app.audit_log.checkpoint import record_checkpoint
from app.audit_log.service import verify_log
from app.certificates.actors import Actor
from app.certificates.service import revoke_certificate
from app.config import get_settings
from app.trust.keys import rotate_signing_key


def fill_every_protected_table(api: TestClient, session: Session, *, reason: str) -> dict[str, Any]:
    """Two vehicles weighed, the study vehicle's refusal issued and revoked for `reason`, a type
    assessment, the signing key rotated and the audit log checkpointed; the inspection and the
    certificate as the API answered them (keys "inspection" and "certificate")."""
    assert api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    weighing = {"registration_number": "BDG 252 QH", "readings": STUDY_READINGS}
    submitted = api.post("/api/v1/inspections", json=weighing)
    assert submitted.status_code == 201, submitted.text
    issued = api.post(f"/api/v1/inspections/{submitted.json()['id']}/certificate")
    assert issued.status_code == 201, issued.text
    second = {**STUDY_VEHICLE, "registration_number": "AGL 7180"}
    assert api.post("/api/v1/vehicles", json=second).status_code == 201
    weighed = api.post(
        "/api/v1/inspections",
        json={"registration_number": "AGL 7180", "readings": STUDY_TYPE_READINGS["AGL 7180"]},
    )
    assert weighed.status_code == 201, weighed.text
    typed = api.post("/api/v1/type-assessments", json={"make": "Bajaj", "model": "RE"})
    assert typed.status_code == 201, typed.text
    revoke_certificate(session, number=issued.json()["number"], actor=Actor.of_cli(), reason=reason)
    rotate_signing_key(session, get_settings())
    record_checkpoint(session, get_settings(), event_id=verify_log(session).events)
    session.close()
    return {"inspection": submitted.json(), "certificate": issued.json()}
