"""The database goes away under a running server, then comes back: 503s that say so, then service.

A real `trikecert serve` process on a database of its own. On PostgreSQL the database stops taking
connections (ALLOW_CONNECTIONS false) and the server's connections are terminated; on SQLite the
database file is moved away. Meanwhile the station API answers 503 with Retry-After and the JSON
error body, the officer pages a 503 "try again in a moment" page, and the log has exactly one
warning line per refused request and no traceback. Once the database is back the very next
requests are served, without a restart.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
import pytest
from served import free_port, wait_until_ready
from sqlalchemy import create_engine, text
from sqlalchemy.engine import make_url
from study_data import STUDY_READINGS

from app.main import create_app

BIN = Path(sys.executable).parent
OFFICER = "officer@example.org"
PASSWORD = "correct horse battery"
HTML = {"Accept": "text/html"}
_TOKEN = re.compile(r'name="csrf_token" value="([^"]*)"')


@dataclass
class Database:
    """A database of the test's own, and how to take it away and bring it back."""

    url: str
    stop: Callable[[], object]
    start: Callable[[], object]


def _admin(server_url: str, sql: str) -> None:
    engine = create_engine(server_url, isolation_level="AUTOCOMMIT")
    try:
        with engine.connect() as connection:
            connection.execute(text(sql))
    finally:
        engine.dispose()


@pytest.fixture
def database(tmp_path: Path) -> Iterator[Database]:
    """PostgreSQL when the suite runs on it (a new database on that server), else an SQLite file."""
    server_url = os.environ.get("TRIKECERT_TEST_DATABASE_URL", "")
    if not server_url.startswith("postgresql"):
        path = tmp_path / "outage.db"
        away = tmp_path / "outage.db.away"
        yield Database(f"sqlite:///{path}", lambda: path.rename(away), lambda: away.rename(path))
        return
    name = f"trikecert_outage_{uuid.uuid4().hex[:12]}"
    _admin(server_url, f'CREATE DATABASE "{name}"')

    def stop() -> None:
        _admin(server_url, f'ALTER DATABASE "{name}" WITH ALLOW_CONNECTIONS false')
        _admin(server_url, f"SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = '{name}'")

    try:
        url = make_url(server_url).set(database=name).render_as_string(hide_password=False)
        yield Database(
            url, stop, lambda: _admin(server_url, f'ALTER DATABASE "{name}" WITH ALLOW_CONNECTIONS true')
        )
    finally:
        _admin(server_url, f'ALTER DATABASE "{name}" WITH ALLOW_CONNECTIONS true')
        _admin(server_url, f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


@dataclass
class Served:
    """The running server, its log, a station key and a signed-in officer's client."""

    station: httpx.Client
    officer: httpx.Client
    csrf_token: str
    log: Path


@pytest.fixture
def served(database: Database, tmp_path: Path) -> Iterator[Served]:
    """`trikecert demo`, an officer account, then `trikecert serve` with its log kept in a file."""
    env = dict(os.environ, TRIKECERT_DATABASE_URL=database.url, TRIKECERT_ENVIRONMENT="test")
    env.pop("PROMETHEUS_MULTIPROC_DIR", None)
    demo = subprocess.run([BIN / "trikecert", "demo"], env=env, capture_output=True, text=True, check=True)
    key = demo.stdout.strip().splitlines()[-1]
    subprocess.run(
        [BIN / "trikecert", "create-user", OFFICER, "--role", "officer", "--name", "Olu Officer"],
        env=env,
        input=PASSWORD + "\n",
        capture_output=True,
        text=True,
        check=True,
    )
    port = free_port()
    log = tmp_path / "server.log"
    with log.open("wb") as sink:
        server = subprocess.Popen(
            [BIN / "trikecert", "serve", "--port", str(port), "--no-migrate"],
            env=env,
            stdout=sink,
            stderr=subprocess.STDOUT,
        )
    base = f"http://127.0.0.1:{port}"
    station = httpx.Client(base_url=base, headers={"Authorization": f"Bearer {key}"}, timeout=30)
    officer = httpx.Client(base_url=base, headers=HTML, timeout=30)
    try:
        wait_until_ready(f"{base}/healthz", server, log=log)
        token = _TOKEN.search(officer.get("/login").text)
        assert token is not None
        signed_in = officer.post(
            "/login", data={"email": OFFICER, "password": PASSWORD, "csrf_token": token[1]}
        )
        assert signed_in.status_code == 303, signed_in.text
        home = officer.get("/")
        csrf = _TOKEN.search(home.text)
        assert csrf is not None, home.text
        yield Served(station, officer, csrf[1], log)
    finally:
        station.close()
        officer.close()
        server.terminate()
        server.wait(timeout=30)


def _warnings(log: Path) -> list[dict[str, str]]:
    lines = [json.loads(line) for line in log.read_text().splitlines() if line.startswith("{")]
    return [entry for entry in lines if entry.get("logger") == "trikecert.database"]


def _assert_api_unavailable(response: httpx.Response) -> None:
    assert response.status_code == 503, response.text
    assert int(response.headers["Retry-After"]) > 0
    assert response.headers["content-type"].startswith("application/json")
    body = response.json()
    assert "try again" in body["detail"]
    assert [(e["field"], e["rule"]) for e in body["errors"]] == [("database", "unavailable")]


def _assert_page_unavailable(response: httpx.Response, advice: str) -> None:
    assert response.status_code == 503, response.text
    assert int(response.headers["Retry-After"]) > 0
    assert response.headers["content-type"].startswith("text/html")
    assert "Sorry, the service is not available right now" in response.text
    assert advice in response.text


def test_a_database_outage_is_a_503_that_says_try_again_and_the_service_recovers_by_itself(
    served: Served, database: Database
) -> None:
    inspection = {"registration_number": "BDG 252 QH", "readings": STUDY_READINGS}
    assert served.station.get("/api/v1/inspections").status_code == 200
    assert served.officer.get("/inspections").status_code == 200
    vehicle_form = {
        "csrf_token": served.csrf_token,
        "registration_number": "KJA 123 XY",
        "make": "Bajaj",
        "model": "RE",
        "wheelbase_m": "2.0",
        "driver_x_m": "0.93",
    }

    database.stop()
    try:
        refused = []
        for _ in range(3):
            answers = [
                served.station.get("/api/v1/inspections"),
                served.station.post("/api/v1/inspections", json=inspection),
                served.station.get("/api/v1/vehicles/BDG252QH"),
            ]
            for answer in answers:
                _assert_api_unavailable(answer)
            pages = [
                served.officer.get("/inspections"),
                served.officer.post("/vehicles/new", data=vehicle_form),
            ]
            _assert_page_unavailable(pages[0], "Try again in a moment")
            assert '<a href="/inspections">Try again</a>' in pages[0].text  # reloads the same page
            _assert_page_unavailable(pages[1], "go back and send the form again")
            refused += answers + pages
            assert served.officer.get("/healthz").status_code == 200
            assert served.officer.get("/readyz").status_code == 503
    finally:
        database.start()

    assert served.station.get("/api/v1/inspections").status_code == 200
    stored = served.station.post("/api/v1/inspections", json=inspection)
    assert stored.status_code == 201, stored.text
    assert served.officer.get(f"/inspections/{stored.json()['id']}").status_code == 200
    assert served.officer.post("/vehicles/new", data=vehicle_form).status_code == 303
    assert served.officer.get("/readyz").status_code == 200

    warnings = _warnings(served.log)
    assert [w["level"] for w in warnings] == ["warning"] * len(refused)
    assert [w["request_id"] for w in warnings] == [r.headers["x-request-id"] for r in refused]
    assert all(w["message"] == "database unavailable" and w["error"] for w in warnings)
    log = served.log.read_text()
    assert "Traceback" not in log
    assert "Internal Server Error" not in log


def test_every_api_operation_documents_the_503_and_its_retry_after() -> None:
    paths = create_app().openapi()["paths"]
    operations = [
        (path, op) for path, ops in paths.items() if path.startswith("/api/") for op in ops.values()
    ]
    assert operations
    for path, operation in operations:
        unavailable = operation["responses"].get("503")
        assert unavailable is not None, path
        assert "Retry-After" in unavailable["headers"], path
