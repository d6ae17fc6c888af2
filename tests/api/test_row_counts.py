"""The control for every "nothing was stored" assertion that reads tests/row_counts.py: an accepted
request does change the counts, table by table, and a table left out is not read."""

from __future__ import annotations

from fastapi.testclient import TestClient
from row_counts import rows_per_table
from sqlalchemy import Engine
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.db import Base


def test_the_counts_see_each_row_the_api_stores_and_only_the_tables_asked_for(
    api: TestClient, engine: Engine
) -> None:
    before = rows_per_table(engine)
    assert set(before) == set(Base.metadata.tables)
    assert api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    inspection = {"registration_number": STUDY_VEHICLE["registration_number"], "readings": STUDY_READINGS}
    assert api.post("/api/v1/inspections", json=inspection).status_code == 201
    after = rows_per_table(engine)
    grown = {name: after[name] - before[name] for name in after if after[name] != before[name]}
    stored = {"vehicle": 1, "seat": 4, "inspection": 1, "reading": 4, "loading_case": 5}
    assert stored.items() <= grown.items(), grown
    assert all(more > 0 for more in grown.values()), grown
    assert set(rows_per_table(engine, leave_out={"vehicle", "seat"})) == set(after) - {"vehicle", "seat"}
