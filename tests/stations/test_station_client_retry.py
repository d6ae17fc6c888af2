"""Done when: a weighing the service rejected (its vehicle not registered yet) is stored once its
cause is fixed, by `trikecert-station retry ID`, against a real `trikecert serve`."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from sqlalchemy import Engine, select
from sqlalchemy.orm import Session
from station_server import Server, count_inspections, seed_station, seed_study_vehicle

from app.inspections.models import Inspection

CLIENT = [sys.executable, "-m", "app.station_client"]
FAST = ["--backoff-base", "0.05", "--backoff-cap", "0.3", "--give-up-after", "20", "--timeout", "5"]


def test_retry_sends_a_rejected_weighing_again_once_its_vehicle_is_registered(
    database_url: str, session: Session, engine: Engine, tmp_path: Path
) -> None:
    _station_id, key = seed_station(session, "Roadside weighbridge")
    csv = tmp_path / "today.csv"
    csv.write_text("registration_number,front_kg,left_rear_kg,right_rear_kg\nBDG 252 QH,108,115,135\n")
    server = Server(database_url)
    env = dict(
        os.environ,
        TRIKECERT_STATION_KEY=key,
        TRIKECERT_STATION_QUEUE=str(tmp_path / "q.db"),
        TRIKECERT_STATION_URL=server.url,
    )
    server.start()
    try:
        first = subprocess.run([*CLIENT, "submit", str(csv), *FAST], env=env, capture_output=True, text=True)
        seed_study_vehicle(session)  # the office registers the vehicle
        retried = subprocess.run([*CLIENT, "retry", "1", *FAST], env=env, capture_output=True, text=True)
        report = subprocess.run([*CLIENT, "report"], env=env, capture_output=True, text=True)
    finally:
        server.stop()

    assert first.returncode == 1, "rejected"
    assert "404: registration_number: no vehicle BDG 252 QH is registered" in first.stdout
    assert "send it again with: trikecert-station retry 1" in first.stdout
    assert retried.returncode == 0, retried.stdout + retried.stderr
    assert "queued again #1 BDG 252 QH (rejected before: 404:" in retried.stdout
    assert "1 delivered, 0 rejected, 0 still queued" in retried.stdout
    assert count_inspections(session) == 1
    (stored,) = session.scalars(select(Inspection))
    assert f"delivered #1     BDG 252 QH   inspection {stored.id}" in report.stdout
    assert "Traceback" not in first.stderr + retried.stderr
