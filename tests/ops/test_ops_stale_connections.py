"""PostgreSQL closes the app's pooled connections while they sit idle (a restart, an administrator's
terminate): the very next requests are served, each stale connection replaced at checkout without
a SELECT sent to find out (app/db.py), on the stations' hot path and through the ORM alike."""

from __future__ import annotations

import time

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import Engine, text
from study_data import STUDY_READINGS, STUDY_VEHICLE

INSPECTIONS = "/api/v1/inspections"
SUBMISSION = {"registration_number": STUDY_VEHICLE["registration_number"], "readings": STUDY_READINGS}


def _terminate_app_connections(owner_engine: Engine, role: str) -> int:
    """Have the server close every connection of the app's role; wait until they are gone."""
    find = text("SELECT pid FROM pg_stat_activity WHERE datname = current_database() AND usename = :role")
    with owner_engine.connect() as admin:
        pids = admin.execute(find, {"role": role}).scalars().all()
        for pid in pids:
            admin.execute(text("SELECT pg_terminate_backend(:pid)"), {"pid": pid})
        deadline = time.monotonic() + 10
        while True:
            admin.rollback()  # pg_stat_activity is read afresh in each transaction
            if admin.execute(find, {"role": role}).first() is None:
                break
            assert time.monotonic() < deadline, "the server did not close the connections"
            time.sleep(0.05)
    return len(pids)


def test_connections_closed_by_the_server_while_idle_are_replaced_not_failed(
    api: TestClient, engine: Engine, owner_engine: Engine
) -> None:
    if engine.dialect.name != "postgresql":
        pytest.skip("SQLite has no server to close a connection")
    assert api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    for _ in range(3):  # the pool now holds idle connections
        assert api.post(INSPECTIONS, json=SUBMISSION).status_code == 201
    closed = _terminate_app_connections(owner_engine, str(engine.url.username))
    assert closed >= 1

    answers = [api.post(INSPECTIONS, json=SUBMISSION).status_code for _ in range(5)]
    answers.append(api.get(INSPECTIONS).status_code)  # a route through the ORM session

    assert answers == [201] * 5 + [200]
