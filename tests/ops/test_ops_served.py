"""The README's path for a newcomer, through real processes: `trikecert demo`, `trikecert serve`,
then a station's curl-like POST of the study's readings answers Table 4."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
from served import free_port, wait_until_ready
from sqlalchemy import Engine
from study_data import STUDY_READINGS

BIN = Path(sys.executable).parent


@pytest.fixture
def served(engine: Engine, database_url: str) -> Iterator[tuple[str, str]]:
    """`trikecert demo` then `trikecert serve` on the test database; yields (base URL, station key)."""
    env = dict(os.environ, TRIKECERT_DATABASE_URL=database_url)
    demo = subprocess.run([BIN / "trikecert", "demo"], env=env, capture_output=True, text=True, check=True)
    key = demo.stdout.strip().splitlines()[-1]
    port = free_port()
    server = subprocess.Popen(
        [BIN / "trikecert", "serve", "--port", str(port), "--workers", "2"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        wait_until_ready(f"{base}/readyz", server)
        yield base, key
    finally:
        server.terminate()
        server.wait(timeout=30)


def test_a_served_station_post_of_the_study_readings_answers_table_4(served: tuple[str, str]) -> None:
    base, key = served
    request = urllib.request.Request(
        f"{base}/api/v1/inspections",
        data=json.dumps({"registration_number": "bdg 252-qh", "readings": STUDY_READINGS}).encode(),
        headers={"Authorization": f"Bearer {key}", "Content-Type": "application/json"},
        method="POST",
    )
    with urllib.request.urlopen(request, timeout=10) as response:
        assert response.status == 201
        body = json.loads(response.read())
    assert [case["compliant"] for case in body["loading_cases"]] == [False, True, False, False, False]
    assert body["max_compliant_occupants"] == 1
    assert response.headers["x-request-id"]
