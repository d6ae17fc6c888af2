"""Idempotency-Key on POST /api/v1/inspections and /api/v1/vehicles: a retry is answered with the first
response, never stored twice; another body under the same key is refused; keys are per station; only
a success is kept as the answer, in the same transaction as what it created; old keys are pruned."""

from __future__ import annotations

from collections.abc import Iterator
from datetime import timedelta
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import Engine, func, select, update
from sqlalchemy.orm import Session
from station_server import count_inspections, seed_study_vehicle

from app.cli import main as trikecert
from app.db import utcnow
from app.idempotency.models import IdempotencyKey
from app.idempotency.service import Claim, lock_id
from app.inspections.models import LoadingCaseRow, Reading
from app.stations.models import Station
from app.stations.service import create_station
from app.vehicles.models import Vehicle

INSPECTIONS = "/api/v1/inspections"
VEHICLES = "/api/v1/vehicles"
STUDY: dict[str, Any] = {
    "registration_number": "BDG 252 QH",
    "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
}
OTHER_READINGS: dict[str, Any] = {
    **STUDY,
    "readings": {**STUDY["readings"], "front_kg": 109, "overall_kg": 360},
}
KTU: dict[str, Any] = {
    "registration_number": "KTU 417 XA",
    "make": "TVS",
    "model": "King",
    "wheelbase_m": 1.95,
    "seats": [{"role": "driver", "x_m": 0.9}, {"role": "passenger", "x_m": 1.6}],
}


@pytest.fixture
def study(api: TestClient, session: Session) -> TestClient:
    """The API signed as a station, with the study's vehicle on file."""
    seed_study_vehicle(session)
    return api


def post(api: TestClient, path: str, body: dict[str, Any], key: str | None, **headers: str) -> Any:
    if key is not None:
        headers["Idempotency-Key"] = key
    return api.post(path, json=body, headers=headers)


def keys_stored(session: Session) -> int:
    session.expire_all()
    return int(session.scalar(select(func.count()).select_from(IdempotencyKey)) or 0)


def test_a_retry_with_the_same_key_and_body_gets_the_first_answer_replayed(
    study: TestClient, session: Session
) -> None:
    first = post(study, INSPECTIONS, STUDY, "a1b2c3d4-0001")
    retry = post(study, INSPECTIONS, STUDY, "a1b2c3d4-0001")

    assert first.status_code == retry.status_code == 201
    assert retry.content == first.content
    assert retry.headers["Idempotent-Replayed"] == "true"
    assert "Idempotent-Replayed" not in first.headers
    assert retry.headers["content-type"] == "application/json"
    assert count_inspections(session) == 1
    assert study.get(f"{INSPECTIONS}/{first.json()['id']}").json() == first.json()


def test_without_the_header_every_post_is_stored(study: TestClient, session: Session) -> None:
    assert post(study, INSPECTIONS, STUDY, None).status_code == 201
    assert post(study, INSPECTIONS, STUDY, None).status_code == 201
    assert count_inspections(session) == 2
    assert keys_stored(session) == 0


def test_the_same_key_with_another_body_is_refused_and_nothing_is_stored(
    study: TestClient, session: Session
) -> None:
    assert post(study, INSPECTIONS, STUDY, "weighing-7").status_code == 201

    refused = post(study, INSPECTIONS, OTHER_READINGS, "weighing-7")

    assert refused.status_code == 422
    problem = refused.json()["errors"][0]
    assert (problem["field"], problem["rule"]) == ("Idempotency-Key", "idempotency_key_reused")
    assert "different request" in refused.json()["detail"]
    assert count_inspections(session) == 1


def test_the_same_body_with_keys_and_spacing_reordered_is_the_same_request(
    study: TestClient, session: Session
) -> None:
    first = post(study, INSPECTIONS, STUDY, "k-order")
    reordered = study.post(
        INSPECTIONS,
        content=b'{"readings": {"overall_kg": 359, "right_rear_kg": 135, "left_rear_kg": 115, '
        b'"front_kg": 108},   "registration_number": "BDG 252 QH"}',
        headers={"Idempotency-Key": "k-order", "Content-Type": "application/json"},
    )
    assert reordered.status_code == 201
    assert reordered.content == first.content
    assert count_inspections(session) == 1


def test_a_key_used_on_another_endpoint_is_refused(study: TestClient, session: Session) -> None:
    assert post(study, VEHICLES, KTU, "shared-key").status_code == 201
    assert post(study, INSPECTIONS, STUDY, "shared-key").status_code == 422
    assert count_inspections(session) == 0


def test_keys_are_scoped_per_station(study: TestClient, client: TestClient, session: Session) -> None:
    _other, other_key = create_station(session, name="Other weighbridge")
    first = post(study, INSPECTIONS, STUDY, "same-key")
    second = client.post(
        INSPECTIONS,
        json=STUDY,
        headers={"Idempotency-Key": "same-key", "Authorization": f"Bearer {other_key}"},
    )
    assert first.status_code == second.status_code == 201
    assert first.json()["id"] != second.json()["id"]
    assert "Idempotent-Replayed" not in second.headers
    assert count_inspections(session) == 2


def test_the_structured_field_form_in_quotes_is_the_same_key(study: TestClient, session: Session) -> None:
    first = post(study, INSPECTIONS, STUDY, "8e03978e-40d5-43e8-bc93-6894a57f9324")
    quoted = post(study, INSPECTIONS, STUDY, '"8e03978e-40d5-43e8-bc93-6894a57f9324"')
    assert quoted.headers["Idempotent-Replayed"] == "true"
    assert quoted.content == first.content


@pytest.mark.parametrize("key", ["", "with space", "x" * 256, "tab\there", '"unbalanced'])
def test_a_malformed_key_is_refused_naming_the_header(study: TestClient, session: Session, key: str) -> None:
    response = study.post(INSPECTIONS, json=STUDY, headers={"Idempotency-Key": key})
    assert response.status_code == 422
    assert response.json()["errors"][0]["field"] == "Idempotency-Key"
    assert count_inspections(session) == 0


def test_a_refusal_is_not_kept_as_the_answer(study: TestClient, session: Session) -> None:
    """A 4xx stores nothing, so the station may correct the weighing and send it under the same key."""
    bad = {**STUDY, "readings": {**STUDY["readings"], "overall_kg": 400}}
    assert post(study, INSPECTIONS, bad, "retry-me").status_code == 422
    assert post(study, INSPECTIONS, bad, "retry-me").status_code == 422
    assert keys_stored(session) == 0

    fixed = post(study, INSPECTIONS, STUDY, "retry-me")
    assert fixed.status_code == 201
    assert "Idempotent-Replayed" not in fixed.headers
    assert count_inspections(session) == 1


@pytest.fixture
def key_not_storable(owner_engine: Engine, session: Session) -> Iterator[None]:
    """Make the database fail the write of any idempotency key, as a power cut in the middle of the
    write would: a trigger (made by the tables' owner) that raises."""
    if owner_engine.dialect.name == "postgresql":
        make = [
            "CREATE FUNCTION test_power_cut() RETURNS trigger AS $$ "
            "BEGIN RAISE EXCEPTION 'power cut while storing the key'; END $$ LANGUAGE plpgsql",
            "CREATE TRIGGER test_power_cut BEFORE INSERT ON idempotency_key "
            "FOR EACH ROW EXECUTE FUNCTION test_power_cut()",
        ]
        drop = ["DROP TRIGGER test_power_cut ON idempotency_key", "DROP FUNCTION test_power_cut()"]
    else:
        make = [
            "CREATE TRIGGER test_power_cut BEFORE INSERT ON idempotency_key "
            "BEGIN SELECT RAISE(ABORT, 'power cut while storing the key'); END"
        ]
        drop = ["DROP TRIGGER test_power_cut"]
    with owner_engine.begin() as connection:
        for statement in make:
            connection.exec_driver_sql(statement)
    yield
    session.rollback()  # the test's reads hold the table until their transaction ends
    with owner_engine.begin() as connection:
        for statement in drop:
            connection.exec_driver_sql(statement)


def test_a_failure_storing_the_key_leaves_neither_the_inspection_nor_the_key(
    study: TestClient, session: Session, key_not_storable: None
) -> None:
    response = post(study, INSPECTIONS, STUDY, "crash-key")

    assert response.status_code == 500
    assert count_inspections(session) == 0, "the inspection went with the key it was stored with"
    assert keys_stored(session) == 0
    for rows in (Reading, LoadingCaseRow):  # written with them, gone with them
        assert session.scalar(select(func.count()).select_from(rows)) == 0


def test_a_server_error_is_not_kept_as_the_answer(
    study: TestClient, session: Session, monkeypatch: pytest.MonkeyPatch
) -> None:
    import app.inspections.submission as hot_path

    def broken(*_args: Any, **_kwargs: Any) -> Any:
        raise RuntimeError("a bug")

    with monkeypatch.context() as patch:
        patch.setattr(hot_path, "inspection_answer", broken)
        assert post(study, INSPECTIONS, STUDY, "after-a-bug").status_code == 500
    assert keys_stored(session) == 0

    retried = post(study, INSPECTIONS, STUDY, "after-a-bug")
    assert retried.status_code == 201
    assert "Idempotent-Replayed" not in retried.headers
    assert count_inspections(session) == 1


def test_a_registration_retried_with_its_key_gets_its_201_not_a_409(
    study: TestClient, session: Session
) -> None:
    first = post(study, VEHICLES, KTU, "register-ktu")
    retry = post(study, VEHICLES, KTU, "register-ktu")
    plain = post(study, VEHICLES, KTU, None)

    assert (first.status_code, retry.status_code, plain.status_code) == (201, 201, 409)
    assert retry.content == first.content
    assert retry.headers["Idempotent-Replayed"] == "true"
    assert session.scalar(
        select(func.count()).select_from(Vehicle).where(Vehicle.registration_key == "KTU417XA")
    )


def test_keys_are_kept_a_day_then_forgotten_and_pruned(study: TestClient, session: Session) -> None:
    assert post(study, INSPECTIONS, STUDY, "old-key").status_code == 201
    assert post(study, INSPECTIONS, STUDY, "fresh-key").status_code == 201
    session.execute(
        update(IdempotencyKey)
        .where(IdempotencyKey.key == "old-key")
        .values(created_at=utcnow() - timedelta(hours=23, minutes=59))
    )
    session.commit()
    assert post(study, INSPECTIONS, OTHER_READINGS, "old-key").status_code == 422, "kept for 24 hours"

    session.execute(
        update(IdempotencyKey)
        .where(IdempotencyKey.key == "old-key")
        .values(created_at=utcnow() - timedelta(hours=25))
    )
    session.commit()
    assert trikecert(["prune-idempotency-keys"]) == 0
    assert keys_stored(session) == 1, "only the fresh key is left"
    reused = post(study, INSPECTIONS, OTHER_READINGS, "old-key")
    assert reused.status_code == 201
    assert "Idempotent-Replayed" not in reused.headers


def test_an_expired_key_not_yet_pruned_counts_as_new(study: TestClient, session: Session) -> None:
    assert post(study, INSPECTIONS, STUDY, "stale").status_code == 201
    session.execute(update(IdempotencyKey).values(created_at=utcnow() - timedelta(hours=30)))
    session.commit()
    again = post(study, INSPECTIONS, OTHER_READINGS, "stale")
    assert again.status_code == 201
    assert count_inspections(session) == 2
    assert keys_stored(session) == 1


def test_on_postgresql_a_retry_while_the_first_still_runs_gets_409(
    study: TestClient, session: Session, engine: Engine
) -> None:
    if engine.dialect.name != "postgresql":
        pytest.skip("SQLite has one writer: a concurrent duplicate waits, then gets the replay")
    station = session.scalars(select(Station)).one()
    lock = lock_id(Claim(station.id, "in-flight", "", ""))
    with engine.connect() as first_request:  # holds the key's lock as a running request would
        first_request.execute(select(func.pg_advisory_lock(lock)))
        response = post(study, INSPECTIONS, STUDY, "in-flight")
        first_request.execute(select(func.pg_advisory_unlock(lock)))

    assert response.status_code == 409
    assert response.json()["errors"][0]["rule"] == "idempotency_key_in_flight"
    assert response.headers["Retry-After"] == "1"
    assert count_inspections(session) == 0
    assert post(study, INSPECTIONS, STUDY, "in-flight").status_code == 201
