"""Certificates issued at the same moment get distinct, consecutive numbers; one inspection gets one."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TypeVar

from certificate_helpers import weigh
from fastapi.testclient import TestClient
from sqlalchemy import Engine, func, select
from study_data import STUDY_VEHICLE

from app import db
from app.certificates.actors import Actor
from app.certificates.models import Certificate
from app.certificates.service import issue_certificate
from app.config import get_settings
from app.trust.numbers import parse_number

T = TypeVar("T")
THREADS = 6


def all_at_once(jobs: list[Callable[[], T]]) -> list[T]:
    """Run the jobs on threads released together; re-raise the first failure."""
    barrier = threading.Barrier(len(jobs))
    results: list[T | None] = [None] * len(jobs)
    errors: list[BaseException] = []

    def run(index: int) -> None:
        barrier.wait()
        try:
            results[index] = jobs[index]()
        except BaseException as error:
            errors.append(error)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(len(jobs))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=120)
    assert not errors, errors
    return [result for result in results if result is not None]


def issue(inspection_id: int) -> Callable[[], tuple[str, bool]]:
    def job() -> tuple[str, bool]:
        with db.get_sessionmaker()() as session:
            issued = issue_certificate(
                session, inspection_id=inspection_id, actor=Actor.of_cli(), settings=get_settings()
            )
            return issued.certificate.number, issued.created

    return job


def test_simultaneous_issues_get_distinct_consecutive_numbers(api: TestClient, engine: Engine) -> None:
    inspections = []
    for index in range(THREADS):
        registration = f"CON {index:03d} AA"
        assert (
            api.post(
                "/api/v1/vehicles", json={**STUDY_VEHICLE, "registration_number": registration}
            ).status_code
            == 201
        )
        inspections.append(weigh(api, registration))
    results = all_at_once([issue(inspection_id) for inspection_id in inspections])
    assert all(created for _number, created in results)
    sequences = sorted(parse_number(number).sequence for number, _created in results)
    assert sequences == list(range(1, THREADS + 1))


def test_simultaneous_issues_for_one_inspection_make_one_certificate(api: TestClient, engine: Engine) -> None:
    assert api.post("/api/v1/vehicles", json=STUDY_VEHICLE).status_code == 201
    inspection_id = weigh(api)
    results = all_at_once([issue(inspection_id) for _ in range(THREADS)])
    assert len({number for number, _created in results}) == 1
    assert sum(created for _number, created in results) == 1
    with db.get_sessionmaker()() as session:
        assert session.scalar(select(func.count()).select_from(Certificate)) == 1
        assert parse_number(results[0][0]).sequence == 1  # the refused attempts left no gap
