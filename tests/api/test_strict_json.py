"""Strict JSON on the station API: a key given twice is refused at any depth, naming the key; every
number refuses a string; and a body of half a million readings, or of more objects than any request
needs, is refused by the bounds of app.api.limits before its values are validated."""

from __future__ import annotations

import json
from typing import Any

import pytest
from fastapi.testclient import TestClient
from openapi_walk import SCHEMA, field_name, leaves, place, resolve, sample, send_json
from row_counts import rows_per_table
from sqlalchemy import Engine
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.api.limits import MAX_LIST_ITEMS, MAX_OBJECTS

VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"
MIB = 1024 * 1024


def counts(engine: Engine) -> dict[str, int]:
    """Rows per table, except the station rate limit's window (every request counts in it)."""
    return rows_per_table(engine, leave_out={"station_rate_window"})


@pytest.fixture
def on_file(api: TestClient) -> TestClient:
    """The station client with the study's vehicle registered."""
    assert api.post(VEHICLES, json=STUDY_VEHICLE).status_code == 201
    return api


def post_raw(api: TestClient, url: str, text: str) -> Any:
    """A body sent exactly as written (json= could not repeat a key)."""
    return api.post(url, content=text.encode(), headers={"Content-Type": "application/json"})


def refused(response: Any, status: int, field: str, rule: str) -> str:
    """The refusal's message, after checking its status, field and rule."""
    assert response.status_code == status, response.text
    problems = {(p["field"], p["rule"]): p["message"] for p in response.json()["errors"]}
    assert (field, rule) in problems, response.text
    return str(problems[(field, rule)])


DUPLICATES = {
    "a reading given twice (the first one negative)": (
        '{"registration_number": "BDG 252 QH", "readings": {"front_kg": -5, "front_kg": 108, '
        '"left_rear_kg": 115, "right_rear_kg": 135}}',
        "readings.front_kg",
    ),
    "the registration given twice": (
        '{"registration_number": "KTU 1", "registration_number": "BDG 252 QH", '
        '"readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135}}',
        "registration_number",
    ),
    "a key twice inside a list item": (
        '{"registration_number": "BDG 252 QH", "readings": {"front_kg": 108, "left_rear_kg": 115, '
        '"right_rear_kg": 135}, "load_items": [{"mass_kg": 10, "x_m": 1}, '
        '{"label": "a", "mass_kg": 10, "x_m": 1, "x_m": 2}]}',
        "load_items[1].x_m",
    ),
    "a key twice in a measured case's readings": (
        '{"registration_number": "BDG 252 QH", "readings": {"front_kg": 108, "left_rear_kg": 115, '
        '"right_rear_kg": 135}, "measured_cases": [{"occupants": 1, "readings": {"front_kg": 120, '
        '"left_rear_kg": 150, "right_rear_kg": 170, "right_rear_kg": 171}}]}',
        "measured_cases[0].readings.right_rear_kg",
    ),
}


@pytest.mark.parametrize("case", DUPLICATES)
def test_a_key_given_twice_is_refused_naming_it_and_nothing_is_stored(
    on_file: TestClient, engine: Engine, case: str
) -> None:
    text, field = DUPLICATES[case]
    before = counts(engine)
    message = refused(post_raw(on_file, INSPECTIONS, text), 422, field, "duplicate_key")
    assert field in message
    assert "more than once" in message
    assert counts(engine) == before


JSON_OPERATIONS = {
    f"{method.upper()} {url}": (method.upper(), url, operation["requestBody"]["content"]["application/json"])
    for url, operations in SCHEMA["paths"].items()
    for method, operation in operations.items()
    if "application/json" in operation.get("requestBody", {}).get("content", {})
}


@pytest.mark.parametrize("operation", JSON_OPERATIONS)
def test_every_json_body_of_the_api_refuses_a_repeated_key(
    on_file: TestClient, engine: Engine, operation: str
) -> None:
    """Each operation with a JSON body, found in the OpenAPI schema: its example with a key repeated."""
    method, url, content = JSON_OPERATIONS[operation]
    example = sample(content["schema"])
    first = next(iter(example))
    text = json.dumps(example)[:-1] + f", {json.dumps(first)}: {json.dumps(example[first])}}}"
    before = counts(engine)
    headers = {"Content-Type": "application/json"}
    response = on_file.request(method, url, content=text.encode(), headers=headers)
    refused(response, 422, first, "duplicate_key")
    assert counts(engine) == before


def number_cases() -> dict[str, tuple[str, str, tuple[str | int, ...], dict[str, Any]]]:
    """Every number and integer of every JSON body, by operation and field."""
    found = {}
    for operation, (method, url, content) in JSON_OPERATIONS.items():
        for leaf, _schema in leaves(content["schema"], "number", "integer"):
            found[f"{operation} {field_name(leaf)}"] = (method, url, leaf, content["schema"])
    return found


NUMBER_CASES = number_cases()


def test_the_walk_finds_the_numbers_of_the_api() -> None:
    wanted = {"POST /api/v1/vehicles model_year", "POST /api/v1/inspections measured_cases[0].occupants"}
    assert wanted <= set(NUMBER_CASES)


@pytest.mark.parametrize("wrong", ["a string", "true"])
@pytest.mark.parametrize("case", NUMBER_CASES)
def test_every_number_of_the_api_refuses_a_string_or_a_boolean(
    api: TestClient, engine: Engine, case: str, wrong: str
) -> None:
    method, url, leaf, schema = NUMBER_CASES[case]
    if url != VEHICLES:
        assert api.post(VEHICLES, json=STUDY_VEHICLE).status_code == 201
    body = place(sample(schema), schema, leaf, None)
    good = sample(next(s for path, s in leaves(schema, "number", "integer") if path == leaf))
    value: Any = str(good) if wrong == "a string" else True
    before = counts(engine)
    response = send_json(api, method, url, place(body, schema, leaf, value))
    assert response.status_code == 422, response.text
    fields = {p["field"] for p in response.json()["errors"]}
    # A reading may be one number or a list of them: the API names it without the index.
    assert field_name(leaf) in fields or field_name(leaf).removesuffix("[0]") in fields, response.text
    assert counts(engine) == before


def test_model_year_as_a_string_is_refused_like_every_other_number(api: TestClient, engine: Engine) -> None:
    response = api.post(VEHICLES, json={**STUDY_VEHICLE, "model_year": "2012"})
    message = refused(response, 422, "model_year", "int_type")
    assert "whole JSON number, not a string" in message
    assert counts(engine)["vehicle"] == 0


def test_half_a_million_readings_in_a_mebibyte_are_refused_before_they_are_validated(
    on_file: TestClient, engine: Engine
) -> None:
    readings = {**STUDY_READINGS, "front_kg": [1] * 524_000}
    text = json.dumps({"registration_number": "BDG 252 QH", "readings": readings}, separators=(",", ":"))
    assert len(text) <= MIB  # under the size limit: it is the count that refuses it
    before = counts(engine)
    message = refused(post_raw(on_file, INSPECTIONS, text), 422, "readings.front_kg", "too_long")
    assert "524000 values" in message
    assert f"no field of the API takes more than {MAX_LIST_ITEMS}" in message
    assert counts(engine) == before


def test_a_body_of_more_objects_than_any_request_needs_is_refused(
    on_file: TestClient, engine: Engine
) -> None:
    items = ",".join(['{"mass_kg": 1, "x_m": 1}'] * (MAX_OBJECTS + 1))
    text = (
        '{"registration_number": "BDG 252 QH", "readings": {"front_kg": 108, "left_rear_kg": 115, '
        f'"right_rear_kg": 135}}, "load_items": [{items}]}}'
    )
    before = counts(engine)
    message = refused(post_raw(on_file, INSPECTIONS, text), 422, "body", "max_objects")
    assert f"more than {MAX_OBJECTS} JSON objects" in message
    assert counts(engine) == before


def test_the_bounds_are_above_every_list_the_api_takes() -> None:
    """No list of any body may be longer than MAX_LIST_ITEMS, or the parser would refuse a valid one."""

    def max_items(node: Any) -> list[int]:
        if isinstance(node, dict):
            node = resolve(node)
            found = [node["maxItems"]] if "maxItems" in node else []
            return found + [n for child in node.values() for n in max_items(child)]
        if isinstance(node, list):
            return [n for child in node for n in max_items(child)]
        return []

    bodies = [content["schema"] for _m, _u, content in JSON_OPERATIONS.values()]
    found = max_items(bodies)
    assert found
    assert max(found) <= MAX_LIST_ITEMS


def test_the_largest_valid_submission_is_within_the_bounds(on_file: TestClient, engine: Engine) -> None:
    """Every list at its longest (readings, seats, load items, measured cases) is stored, not refused."""
    many = [108] * 20
    seats = [{"role": "driver", "x_m": 0.9303}] + [{"role": "passenger", "x_m": 1.6303}] * 3
    body = {
        "registration_number": "BDG 252 QH",
        "readings": {"front_kg": many, "left_rear_kg": [115] * 20, "right_rear_kg": [135] * 20},
        "occupants": {"mass_kg": 72, "seats": seats},
        "load_items": [{"label": f"box {i}", "mass_kg": 1, "x_m": 1.5} for i in range(10)],
        "measured_cases": [
            {"occupants": n, "readings": {"front_kg": [108] * 20, "left_rear_kg": 115, "right_rear_kg": 135}}
            for n in range(1, 5)
        ],
    }
    response = on_file.post(INSPECTIONS, json=body)
    assert response.status_code == 201, response.text
    assert counts(engine)["inspection"] == 1
