"""Health, readiness, metrics and request ids, as an operator or a load balancer sees them."""

from __future__ import annotations

import functools
import multiprocessing
import re

from access_lines import access_lines
from fastapi.testclient import TestClient
from sqlalchemy import Engine, text
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.ops.requests import request_id_of


def test_healthz_answers_ok_and_carries_a_request_id(client: TestClient) -> None:
    response = client.get("/healthz")
    assert response.status_code == 200
    assert response.json() == {"status": "ok"}
    assert len(response.headers["x-request-id"]) == 32


def test_a_sane_request_id_from_the_caller_is_echoed_and_a_hostile_one_replaced(client: TestClient) -> None:
    assert (
        client.get("/healthz", headers={"X-Request-ID": "lb-1234.abc"}).headers["x-request-id"]
        == "lb-1234.abc"
    )
    replaced = client.get("/healthz", headers={"X-Request-ID": "bad id\twith spaces"}).headers["x-request-id"]
    assert replaced != "bad id\twith spaces"
    assert len(replaced) == 32


def test_request_ids_differ_between_requests_and_between_forked_workers() -> None:
    """Workers are forked from one process: each must make ids of its own, not replay the parent's."""
    ids_of = functools.partial(_new_ids, 50)
    with multiprocessing.get_context("fork").Pool(2) as workers:
        in_workers = workers.map(ids_of, range(2))
    here = ids_of(0)
    every = [*here, *in_workers[0], *in_workers[1]]
    assert len(set(every)) == len(every) == 150
    assert all(re.fullmatch(r"[0-9a-f]{32}", request_id) for request_id in every)


def _new_ids(count: int, _worker: int) -> list[str]:
    return [request_id_of({"type": "http", "headers": []}) for _ in range(count)]


def test_readyz_is_ready_when_the_database_is_migrated(client: TestClient) -> None:
    response = client.get("/readyz")
    assert response.status_code == 200
    assert response.json() == {"status": "ok"}


def test_readyz_says_503_when_migrations_are_behind(client: TestClient, owner_engine: Engine) -> None:
    with owner_engine.begin() as connection:  # the revision is the owner's to set, not the app's
        (head,) = connection.execute(text("SELECT version_num FROM alembic_version")).one()
        connection.execute(text("UPDATE alembic_version SET version_num = 'behind'"))
    try:
        response = client.get("/readyz")
        assert response.status_code == 503
        assert "migrate" in response.json()["reason"]
    finally:
        with owner_engine.begin() as connection:
            connection.execute(text("UPDATE alembic_version SET version_num = :head"), {"head": head})


def test_metrics_count_requests_and_stored_inspections_by_verdict(api: TestClient) -> None:
    api.post("/api/v1/vehicles", json=STUDY_VEHICLE)
    submitted = api.post(
        "/api/v1/inspections", json={"registration_number": "BDG252QH", "readings": STUDY_READINGS}
    )
    assert submitted.status_code == 201
    api.get("/healthz")
    body = api.get("/metrics").text
    assert 'trikecert_http_requests_total{handler="healthz",method="GET",status="200"}' in body
    assert 'trikecert_http_requests_total{handler="create_inspection",method="POST",status="201"}' in body
    assert 'trikecert_inspections{verdict="non_compliant"} 1.0' in body
    assert 'trikecert_inspections{verdict="compliant"} 0.0' in body
    assert "trikecert_http_request_duration_seconds_bucket" in body
    assert 'trikecert_certificates{verdict="non_compliant"} 0.0' in body
    issued = api.post(f"/api/v1/inspections/{submitted.json()['id']}/certificate")
    assert issued.status_code == 201
    assert 'trikecert_certificates{verdict="non_compliant"} 1.0' in api.get("/metrics").text


def test_a_probe_answered_ahead_of_the_framework_is_still_logged_with_its_headers(client: TestClient) -> None:
    with access_lines() as lines:
        response = client.get("/healthz", headers={"X-Request-ID": "probe-1", "X-Forwarded-Proto": "https"})

    assert response.status_code == 200
    assert response.headers["content-type"] == "application/json"
    assert response.headers["x-content-type-options"] == "nosniff"
    assert "server" not in response.headers
    assert "strict-transport-security" not in response.headers, "https said by no trusted proxy"
    [line] = lines
    assert line["path"] == "/healthz"
    assert (line["handler"], line["status"], line["request_id"]) == ("healthz", 200, "probe-1")


def test_other_methods_on_the_probe_reach_the_route_and_are_refused(client: TestClient) -> None:
    assert client.post("/healthz").status_code == 405
