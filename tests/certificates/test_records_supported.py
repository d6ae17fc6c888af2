"""The database itself refuses a certificate its records do not support, and a plate moved to another
vehicle (issue 27, items 1 and 3): the insider's attempts, made with raw SQL as the app's own role
(PostgreSQL; on SQLite, on the file), are each refused by the triggers, and nothing is stored."""

from __future__ import annotations

import json
from datetime import timedelta
from typing import Any

import pytest
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, weigh
from fastapi.testclient import TestClient
from sqlalchemy import Engine, Table, func, insert, select, text, update
from sqlalchemy.exc import DBAPIError
from sqlalchemy.orm import Session

from app.audit.models import AuditEvent
from app.audit_log.service import verify_log
from app.certificates.actors import Actor
from app.certificates.facts import facts_of
from app.certificates.guard import ImmutableRecord, immutability_lifted
from app.certificates.models import Certificate, CertificateRevocation
from app.certificates.service import reissue_certificate, revoke_certificate
from app.config import get_settings
from app.errors import Conflict
from app.inspections.models import Inspection
from app.vehicles.models import Vehicle

CERTIFICATE: Table = Certificate.__table__  # type: ignore[assignment]
REVOCATION: Table = CertificateRevocation.__table__  # type: ignore[assignment]
AUDIT_EVENT: Table = AuditEvent.__table__  # type: ignore[assignment]
VEHICLE: Table = Vehicle.__table__  # type: ignore[assignment]
STUDY_PLATE, FRONT_HEAVY_PLATE = "BDG 252 QH", "KTU 417 XA"
# The front-heavy trike loaded at the back: every case fails.
REAR_HEAVY_READINGS = {"front_kg": 60, "left_rear_kg": 150, "right_rear_kg": 150}


@pytest.fixture
def records(api: TestClient) -> dict[str, Any]:
    """Two vehicles registered; the study vehicle weighed (not compliant) and its refusal issued."""
    register(api)
    register(api, FRONT_HEAVY)
    study_inspection = weigh(api)
    refusal = certify(api, study_inspection)
    assert refusal["kind"] == "refusal"
    return {"study_inspection": study_inspection, "refusal": refusal}


def stored(engine: Engine, number: str) -> dict[str, Any]:
    """A stored certificate's row, every column."""
    with engine.connect() as connection:
        return dict(
            connection.execute(select(CERTIFICATE).where(CERTIFICATE.c.number == number)).one()._mapping
        )


def vehicle_id(engine: Engine, plate: str) -> int:
    with engine.connect() as connection:
        return int(
            connection.execute(
                select(VEHICLE.c.id).where(VEHICLE.c.registration_number == plate)
            ).scalar_one()
        )


def facts_for(session: Session, inspection_id: int) -> dict[str, Any]:
    """The facts a certificate of this inspection prints, made as the service makes them."""
    facts = facts_of(session, session.get_one(Inspection, inspection_id), authority="insider")
    session.rollback()
    return facts.to_json()


def forged(template: dict[str, Any], **changes: Any) -> dict[str, Any]:
    """A certificate row as an insider would write it: a genuine one's columns, renumbered and changed."""
    row = {**template, "number": "TRK-2026-990001-X", "year": 2026, "sequence": 990001, **changes}
    row.pop("id")
    return row


def refused(engine: Engine, table: Table, row: dict[str, Any]) -> str:
    """Insert one row in a transaction of its own and commit; the database's refusal (at the INSERT
    or, for PostgreSQL's deferred checks, at commit), or fail."""
    with engine.connect() as connection, pytest.raises(DBAPIError) as raised, connection.begin():
        connection.execute(insert(table), row)
    message = str(raised.value.orig)
    assert "trikecert" in message, message
    return message


def certificate_count(engine: Engine) -> int:
    with engine.connect() as connection:
        return int(connection.scalar(select(func.count()).select_from(CERTIFICATE)) or 0)


def test_a_compliant_certificate_for_a_non_compliant_inspection_is_refused(
    records: dict[str, Any], engine: Engine
) -> None:
    genuine = stored(engine, records["refusal"]["number"])
    for changes in (
        {"kind": "compliant", "compliant": True, "max_compliant_occupants": 3},
        {"kind": "refusal", "compliant": False, "max_compliant_occupants": 3},
    ):
        row = forged(genuine, supersedes_id=genuine["id"], **changes)
        assert "loading cases" in refused(engine, CERTIFICATE, row)
    # Nor may the facts it prints (the page's occupancy and Table 4) say more than the row.
    facts = genuine["facts"]
    printed = {
        **facts,
        "compliant": True,
        "max_compliant_occupants": 3,
        "cases": [{**case, "compliant": True} for case in facts["cases"]],
    }
    for lie in (
        {"compliant": True},
        {"max_compliant_occupants": 3},
        {"cases": printed["cases"]},
        {"vehicle": {**facts["vehicle"], "registration_number": FRONT_HEAVY_PLATE}},
    ):
        row = forged(genuine, supersedes_id=genuine["id"], facts={**facts, **lie})
        assert "facts" in refused(engine, CERTIFICATE, row)
    # The kind must say what the verdict says.
    row = forged(genuine, supersedes_id=genuine["id"], kind="compliant")
    assert "kind" in refused(engine, CERTIFICATE, row)
    assert certificate_count(engine) == 1


def test_a_certificate_on_another_plate_or_vehicle_than_weighed_is_refused(
    records: dict[str, Any], engine: Engine
) -> None:
    genuine = stored(engine, records["refusal"]["number"])
    other = vehicle_id(engine, FRONT_HEAVY_PLATE)
    for changes in ({"registration_number": FRONT_HEAVY_PLATE}, {"vehicle_id": other, "supersedes_id": None}):
        row = forged(genuine, **{"supersedes_id": genuine["id"], **changes})
        assert "weighed" in refused(engine, CERTIFICATE, row)


def test_a_certificate_of_an_earlier_weighing_that_a_later_one_contradicts_is_refused(
    records: dict[str, Any], api: TestClient, engine: Engine, session: Session
) -> None:
    genuine = stored(engine, records["refusal"]["number"])
    passed = weigh(api, FRONT_HEAVY_PLATE, FRONT_HEAVY_READINGS)
    failed = weigh(api, FRONT_HEAVY_PLATE, REAR_HEAVY_READINGS)
    row = forged(
        genuine,
        kind="compliant",
        compliant=True,
        max_compliant_occupants=2,
        inspection_id=passed,
        facts=facts_for(session, passed),
        vehicle_id=vehicle_id(engine, FRONT_HEAVY_PLATE),
        registration_number=FRONT_HEAVY_PLATE,
        supersedes_id=None,
    )
    assert "found otherwise" in refused(engine, CERTIFICATE, row)
    # The app says so first, and certifies the newest weighing.
    answer = api.post(f"/api/v1/inspections/{passed}/certificate")
    assert answer.status_code == 409, answer.text
    assert answer.json()["errors"][0]["rule"] == "newer_inspection"
    assert certify(api, failed)["kind"] == "refusal"


def test_a_reissue_after_a_later_weighing_found_otherwise_is_refused(
    records: dict[str, Any], api: TestClient, session: Session
) -> None:
    passed = weigh(api, FRONT_HEAVY_PLATE, FRONT_HEAVY_READINGS)
    compliant = certify(api, passed)
    weigh(api, FRONT_HEAVY_PLATE, REAR_HEAVY_READINGS)
    with pytest.raises(Conflict) as raised:
        reissue_certificate(
            session, number=compliant["number"], actor=Actor.of_cli(), reason="lost", settings=get_settings()
        )
    assert [problem.rule for problem in raised.value.problems] == ["newer_inspection"]


def test_a_certificate_that_does_not_supersede_the_current_one_is_refused(
    records: dict[str, Any], engine: Engine
) -> None:
    genuine = stored(engine, records["refusal"]["number"])
    # A second current refusal beside the first (a reissue that supersedes nothing).
    assert "must supersede" in refused(engine, CERTIFICATE, forged(genuine, supersedes_id=None))


def test_a_certificate_without_its_audit_event_is_refused(
    records: dict[str, Any], api: TestClient, engine: Engine, session: Session
) -> None:
    genuine = stored(engine, records["refusal"]["number"])
    passed = weigh(api, FRONT_HEAVY_PLATE, FRONT_HEAVY_READINGS)
    row = forged(
        genuine,
        kind="compliant",
        compliant=True,
        max_compliant_occupants=2,
        inspection_id=passed,
        facts=facts_for(session, passed),
        vehicle_id=vehicle_id(engine, FRONT_HEAVY_PLATE),
        registration_number=FRONT_HEAVY_PLATE,
        supersedes_id=None,
    )
    # Every fact agrees with the inspection: only the audit event is missing.
    assert "audit event" in refused(engine, CERTIFICATE, row)
    assert certificate_count(engine) == 1
    if engine.dialect.name == "postgresql":
        # An event written beforehand, in a transaction of its own, is not the certificate's own.
        event = {"kind": "compliant", "registration_number": FRONT_HEAVY_PLATE, "inspection_id": passed}
        with engine.begin() as connection:
            last = connection.execute(text("SELECT id, hash FROM audit_event ORDER BY id DESC LIMIT 1")).one()
            connection.execute(
                insert(AUDIT_EVENT),
                {
                    "id": last.id + 1,
                    "occurred_at": genuine["issued_at"],
                    "actor_kind": "anonymous",
                    "actor_label": "insider",
                    "action": "certificate.issued",
                    "target_type": "certificate",
                    "target_id": row["number"],
                    "details": json.dumps(event, separators=(",", ":"), sort_keys=True),
                    "previous_hash": last.hash,
                    "hash": "f" * 64,
                },
            )
        assert "audit event" in refused(engine, CERTIFICATE, row)
    assert certify(api, passed)["kind"] == "compliant"  # the app's own issue, with its event, goes in


def test_a_revocation_without_its_audit_event_is_refused(records: dict[str, Any], engine: Engine) -> None:
    genuine = stored(engine, records["refusal"]["number"])
    row = {
        "certificate_id": genuine["id"],
        "revoked_at": genuine["issued_at"] + timedelta(days=1),
        "revoked_by": "insider",
        "reason": "quietly",
    }
    message = refused(engine, REVOCATION, row)
    assert "revocation" in message
    assert "audit event" in message


def test_a_vehicles_plate_is_never_changed_in_place(
    records: dict[str, Any], engine: Engine, owner_engine: Engine, session: Session
) -> None:
    swap = (
        "UPDATE vehicle SET "
        f"registration_number = CASE registration_number WHEN '{STUDY_PLATE}' THEN '{FRONT_HEAVY_PLATE}' "
        f"ELSE '{STUDY_PLATE}' END, "
        "registration_key = CASE registration_key WHEN 'BDG252QH' THEN 'KTU417XA' ELSE 'BDG252QH' END "
        f"WHERE registration_number IN ('{STUDY_PLATE}', '{FRONT_HEAVY_PLATE}')"
    )
    rename = (
        f"UPDATE vehicle SET registration_number = 'BDG 252 QX' WHERE registration_number = '{STUDY_PLATE}'"
    )
    for statement in (swap, rename):
        if engine.dialect.name == "postgresql":  # the app's role may not update a vehicle at all
            with engine.connect() as connection, pytest.raises(DBAPIError, match="permission denied"):
                connection.execute(text(statement))
        with owner_engine.connect() as connection, pytest.raises(DBAPIError) as raised:
            connection.execute(text(statement))
        assert "changed in place" in str(raised.value.orig)
    vehicle = session.scalars(select(Vehicle).where(Vehicle.registration_number == STUDY_PLATE)).one()
    vehicle.registration_number = FRONT_HEAVY_PLATE
    with pytest.raises(ImmutableRecord, match="registration"):
        session.commit()
    session.rollback()
    with engine.connect() as connection:
        plates = connection.execute(select(VEHICLE.c.registration_number).order_by(VEHICLE.c.id)).scalars()
        assert list(plates) == [STUDY_PLATE, FRONT_HEAVY_PLATE]


def test_an_inspection_under_another_plate_than_its_vehicles_is_refused(
    records: dict[str, Any], engine: Engine
) -> None:
    with engine.connect() as connection:
        weighed = dict(
            connection.execute(
                select(Inspection.__table__).where(Inspection.__table__.c.id == records["study_inspection"])
            )
            .one()
            ._mapping
        )
    weighed.pop("id")
    inspection: Table = Inspection.__table__  # type: ignore[assignment]
    assert "is not that of" in refused(
        engine, inspection, {**weighed, "registration_number": FRONT_HEAVY_PLATE}
    )


def test_records_keep_the_plate_as_weighed(
    records: dict[str, Any], client: TestClient, api: TestClient, owner_engine: Engine, engine: Engine
) -> None:
    number = records["refusal"]["number"]
    with engine.connect() as connection:
        kept = connection.scalar(
            select(Inspection.registration_number).where(Inspection.id == records["study_inspection"])
        )
    assert kept == STUDY_PLATE
    # Even a plate rewritten behind the app's back (the owner, with the triggers lifted) does not move
    # what the inspection and the certificate say was weighed.
    with owner_engine.begin() as connection, immutability_lifted(connection):
        connection.execute(
            update(VEHICLE)
            .where(VEHICLE.c.registration_number == STUDY_PLATE)
            .values(registration_number="ZZZ 999 ZZ", registration_key="ZZZ999ZZ")
        )
    inspection = api.get(f"/api/v1/inspections/{records['study_inspection']}")
    assert inspection.json()["registration_number"] == STUDY_PLATE
    assert api.get(f"/api/v1/certificates/{number}").json()["registration_number"] == STUDY_PLATE
    page = client.get(f"/verify/{number}")
    assert f'<span id="registration">{STUDY_PLATE}</span>' in page.text
    assert "ZZZ 999 ZZ" not in page.text


def test_the_apps_own_issue_reissue_and_revoke_pass_the_triggers_and_are_logged(
    records: dict[str, Any], session: Session
) -> None:
    number = records["refusal"]["number"]
    actor = Actor.of_cli()
    reissued = reissue_certificate(
        session, number=number, actor=actor, reason="lost", settings=get_settings()
    )
    revoke_certificate(session, number=reissued.number, actor=actor, reason="weighed wrongly")
    events = session.scalars(
        select(AuditEvent).where(AuditEvent.target_type == "certificate").order_by(AuditEvent.id)
    ).all()
    assert [(event.action, event.target_id) for event in events] == [
        ("refusal.issued", number),
        ("refusal.issued", reissued.number),
        ("certificate.revoked", reissued.number),
    ]
    assert verify_log(session).intact
