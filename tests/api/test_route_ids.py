"""Every id a path or query carries is bounded before it reaches the database, on every route.

The routes come from the app's own route table, so a route added tomorrow is tried too. Each path
parameter and each declared query parameter is filled with numbers no record can have (0, -1, 2^31,
which overflows PostgreSQL's INTEGER, 2^63, which overflows SQLite's, and 10^30), sent with the
right method and credentials: a station key on the API, a signed-in administrator's session and CSRF
token on the pages. Nothing answers 5xx; an id in a path answers 422 naming it on the API (its schema
states the bounds) and the "Page not found" page on the officer pages.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import pytest
from fastapi import FastAPI
from fastapi.dependencies.models import Dependant
from fastapi.routing import iter_route_contexts
from fastapi.testclient import TestClient
from httpx2 import Response
from sqlalchemy import Engine
from sqlalchemy.orm import Session
from web.webtools import ADMIN_EMAIL, PASSWORD, hidden, sign_in

from app import cli
from app.accounts.service import create_user
from app.ids import MAX_ID
from app.main import create_app

OUT_OF_RANGE = ["0", "-1", str(2**31), str(2**63), str(10**30)]
HTML = {"Accept": "text/html,application/xhtml+xml"}


@dataclass(frozen=True)
class Operation:
    """One method of one route, with the names of its path parameters (int ones apart) and queries."""

    method: str
    path: str
    id_params: tuple[str, ...]
    other_path_params: tuple[str, ...]
    query_params: tuple[str, ...]

    @property
    def api(self) -> bool:
        """Served to stations (JSON, station key) rather than to officers."""
        return self.path.startswith("/api/")

    def url(self, name: str, value: str) -> str:
        """The path with `name` set to `value` and every other path parameter to 1."""
        path = self.path
        for param in (*self.id_params, *self.other_path_params):
            path = path.replace("{" + param + "}", value if param == name else "1")
        return path

    def __str__(self) -> str:
        return f"{self.method} {self.path}"


def _params(dependant: Dependant, kind: str) -> list[Any]:
    """The route's parameters of one kind, its dependencies' included."""
    found = list(getattr(dependant, kind))
    for child in dependant.dependencies:
        found += [p for p in _params(child, kind) if p.name not in {f.name for f in found}]
    return found


def operations(app: FastAPI) -> list[Operation]:
    """Every method of every route of the app that takes a parameter, from its route table."""
    found: list[Operation] = []
    for route in iter_route_contexts(app.routes):
        dependant = getattr(route, "dependant", None)
        if dependant is None:
            continue  # /openapi.json, /docs, /static: no parameters of ours
        path_params = _params(dependant, "path_params")
        ints = tuple(p.name for p in path_params if p.field_info.annotation is int)
        others = tuple(p.name for p in path_params if p.name not in ints)
        queries = tuple(p.alias for p in _params(dependant, "query_params"))
        if not (ints or others or queries):
            continue
        for method in sorted(route.methods or ()):
            if method != "HEAD":
                found.append(Operation(method, str(route.path), ints, others, queries))
    return found


OPERATIONS = operations(create_app())
WITH_ID = [op for op in OPERATIONS if op.id_params]


def test_the_route_table_has_the_id_routes_this_test_is_meant_to_try() -> None:
    """A guard against an empty or partial enumeration: the routes named in the issue are all there."""
    expected = {
        "GET /api/v1/inspections/{inspection_id}",
        "POST /api/v1/inspections/{inspection_id}/certificate",
        "GET /inspections/{inspection_id}",
        "POST /inspections/{inspection_id}/certificate",
        "GET /admin/stations/{station_id}",
        "POST /admin/stations/{station_id}",
        "POST /admin/stations/{station_id}/key",
        "POST /admin/stations/{station_id}/disable",
        "POST /admin/stations/{station_id}/enable",
        "POST /admin/users/{user_id}/disable",
        "POST /admin/users/{user_id}/enable",
        "GET /admin/users/{user_id}/password",
        "POST /admin/users/{user_id}/password",
    }
    assert expected <= {str(op) for op in WITH_ID}
    pages = {str(op): op.query_params for op in OPERATIONS}
    assert {"station", "page"} <= set(pages["GET /inspections"])
    assert "station" in pages["GET /statistics"]
    audit_filters = {"actor", "actor_kind", "action", "record_type", "record_id", "from", "to"}
    assert audit_filters | {"page"} <= set(pages["GET /admin/audit"])
    assert audit_filters <= set(pages["GET /admin/audit.csv"])


@dataclass
class Caller:
    """Sends a request as the operation's user: a station on the API, a signed-in admin on the pages."""

    client: TestClient
    station_key: str
    csrf_token: str

    def send(self, op: Operation, url: str, params: dict[str, str] | None = None) -> Response:
        """The request, signed as the operation needs."""
        if op.api:
            headers = {"Authorization": f"Bearer {self.station_key}"}
            answer: Response = self.client.request(op.method, url, params=params, headers=headers)
            return answer
        data = {"csrf_token": self.csrf_token} if op.method == "POST" else None
        response: Response = self.client.request(
            op.method, url, params=params, data=data, headers=HTML, follow_redirects=False
        )
        return response


@pytest.fixture
def caller(client: TestClient, session: Session, station_key: str) -> Caller:
    """The app's client signed in as an administrator, with a station key for the API."""
    create_user(session, email=ADMIN_EMAIL, password=PASSWORD, role="admin")
    assert sign_in(client, ADMIN_EMAIL).status_code == 303
    return Caller(client, station_key, hidden(client.get("/", headers=HTML).text))


def _refusal_problem(op: Operation, name: str, value: str, response: Response) -> str | None:
    """What is wrong with the answer to an out-of-range id, or None when it is the promised refusal."""
    where = f"{op} with {name}={value}: {response.status_code} {response.text[:200]}"
    if op.api:
        fields = (
            [e.get("field") for e in response.json().get("errors", [])] if response.status_code == 422 else []
        )
        return None if fields == [name] else where
    return None if response.status_code == 404 and "Page not found" in response.text else where


def test_an_id_no_record_can_have_is_refused_on_every_route_before_the_database(caller: Caller) -> None:
    problems = [
        _refusal_problem(op, name, value, caller.send(op, op.url(name, value)))
        for op in WITH_ID
        for name in op.id_params
        for value in OUT_OF_RANGE
    ]
    assert [p for p in problems if p] == []


def test_the_largest_id_is_an_ordinary_not_found_on_every_route(caller: Caller) -> None:
    problems = []
    for op in WITH_ID:
        for name in op.id_params:
            response = caller.send(op, op.url(name, str(MAX_ID)))
            # A page's form naming a missing record answers its 404, or goes back to the record's page.
            expected = (404,) if op.api or op.method == "GET" else (303, 404)
            if response.status_code not in expected:
                problems.append(f"{op}: {response.status_code} {response.text[:200]}")
    assert problems == []


def test_numbers_in_any_text_path_parameter_or_query_parameter_are_no_server_error(caller: Caller) -> None:
    problems = []
    for op in OPERATIONS:
        for value in [*OUT_OF_RANGE, str(MAX_ID), "1" * 40]:
            tried: list[tuple[str, str, dict[str, str] | None]] = [
                (f"{name}={value}", op.url(name, value), None) for name in op.other_path_params
            ]
            tried += [(f"?{name}={value}", op.url("", "1"), {name: value}) for name in op.query_params]
            for what, url, params in tried:
                response = caller.send(op, url, params)
                if response.status_code >= 500:
                    problems.append(f"{op} with {what}: {response.status_code} {response.text[:200]}")
    assert problems == []


def test_a_station_filter_no_station_can_have_is_refused_beside_the_field(caller: Caller) -> None:
    for page in ("/inspections", "/statistics"):
        for value in OUT_OF_RANGE:
            response = caller.client.get(page, params={"station": value}, headers=HTML)
            assert response.status_code == 422, f"{page}?station={value}: {response.status_code}"
            assert "Choose a station from the list" in response.text


def test_a_list_page_number_no_list_can_reach_is_page_not_found(caller: Caller) -> None:
    for value in OUT_OF_RANGE:
        response = caller.client.get("/inspections", params={"page": value}, headers=HTML)
        assert response.status_code == 404, f"page={value}: {response.status_code}"
        assert "Page not found" in response.text


@pytest.mark.parametrize("value", OUT_OF_RANGE)
def test_the_command_line_refuses_an_id_no_record_can_have(
    value: str, engine: Engine, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as usage:
        cli.main(["issue-certificate", value])
    assert usage.value.code == 2
    assert "is not an id (a whole number from 1 to 2147483647)" in capsys.readouterr().err
    assert cli.main(["disable-station", value]) != 0
    assert f"no station is named '{value}'" in capsys.readouterr().err
