"""Every kind of bad input to the station API gets a 4xx whose body names the field and the rule, and
nothing is stored: the vehicle, seat, inspection, reading and loading_case tables are counted before
and after each refused request.

The study's vehicle (BDG 252 QH, wheelbase 2.000 m, driver at 0.9303 m, three passengers at
1.6303 m) is on file before each request, so a refusal is never just "unknown vehicle".
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.db import Base

TABLES = ("vehicle", "seat", "inspection", "reading", "loading_case")
MIB = 1024 * 1024

OTHER_VEHICLE: dict[str, Any] = {
    "registration_number": "KTU 417 XA",
    "make": "TVS",
    "model": "King",
    "wheelbase_m": 1.95,
    "seats": [{"role": "driver", "x_m": 0.9}, {"role": "passenger", "x_m": 1.6}],
}


def vehicle(**changes: Any) -> dict[str, Any]:
    """A valid new vehicle (not yet on file) with `changes`."""
    return {**OTHER_VEHICLE, **changes}


def inspection(readings: dict[str, Any] | None = None, **changes: Any) -> dict[str, Any]:
    """A valid submission for the study's vehicle, its readings updated with `readings`, then `changes`."""
    readings = {**STUDY_READINGS, **(readings or {})}
    return {"registration_number": "BDG 252 QH", "readings": readings, **changes}


def raw(text: str) -> bytes:
    """A body sent byte for byte (for NaN and Infinity, which Python's json writes and reads)."""
    return text.encode()


@dataclasses.dataclass(frozen=True)
class Bad:
    """One bad request and the refusal it must get."""

    method: str
    path: str
    status: int
    field: str
    rule: str
    words: tuple[str, ...]  # the message must contain each of these
    json: Any = None
    content: bytes | None = None
    headers: dict[str, str] = dataclasses.field(default_factory=dict)
    signed: bool = True


VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"

BAD: dict[str, Bad] = {
    # Authentication
    "no Authorization header on a registration": Bad(
        "POST",
        VEHICLES,
        401,
        "Authorization",
        "authentication",
        ("Authorization", "Bearer"),
        json=vehicle(),
        signed=False,
    ),
    "no Authorization header on a submission": Bad(
        "POST",
        INSPECTIONS,
        401,
        "Authorization",
        "authentication",
        ("Authorization", "Bearer"),
        json=inspection(),
        signed=False,
    ),
    "a wrong station key": Bad(
        "POST",
        INSPECTIONS,
        401,
        "Authorization",
        "authentication",
        ("Authorization", "not recognised"),
        json=inspection(),
        signed=False,
        headers={"Authorization": "Bearer tks_not-a-key-of-any-station"},
    ),
    "a key under another scheme": Bad(
        "POST",
        VEHICLES,
        401,
        "Authorization",
        "authentication",
        ("Authorization", "Bearer"),
        json=vehicle(),
        signed=False,
        headers={"Authorization": "Basic dGVzdDp0ZXN0"},
    ),
    # Not JSON, or not a JSON object
    "malformed JSON in a registration": Bad(
        "POST",
        VEHICLES,
        400,
        "body",
        "json_invalid",
        ("body", "not valid JSON"),
        content=raw('{"registration_number": "KTU 417 XA", "make": '),
    ),
    "malformed JSON in a submission": Bad(
        "POST",
        INSPECTIONS,
        400,
        "body",
        "json_invalid",
        ("body", "not valid JSON"),
        content=raw('{"registration_number": "BDG 252 QH", "readings": {"front_kg": 108,}}'),
    ),
    "a JSON list instead of an object": Bad(
        "POST",
        INSPECTIONS,
        422,
        "body",
        "model_attributes_type",
        ("body", "one JSON object"),
        json=[STUDY_READINGS],
    ),
    "an empty body": Bad(
        "POST",
        VEHICLES,
        422,
        "body",
        "missing",
        ("body", "one JSON object"),
        content=b"",
    ),
    "JSON sent as text/plain": Bad(
        "POST",
        INSPECTIONS,
        422,
        "body",
        "model_attributes_type",
        ("Content-Type: application/json",),
        content=raw(json.dumps(inspection())),
        headers={"Content-Type": "text/plain"},
    ),
    # Wrong types
    "a string where a weight is required": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg",
        "number_type",
        ("readings.front_kg", "JSON number", "string"),
        json=inspection({"front_kg": "108"}),
    ),
    "a boolean where a weight is required": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.left_rear_kg",
        "number_type",
        ("readings.left_rear_kg", "JSON number", "true or false"),
        json=inspection({"left_rear_kg": True}),
    ),
    "an object where a weight is required": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.right_rear_kg",
        "number_type",
        ("readings.right_rear_kg", "JSON number", "object"),
        json=inspection({"right_rear_kg": {"kg": 135}}),
    ),
    "a string among repeated readings": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg[1]",
        "number_type",
        ("readings.front_kg[1]", "JSON number"),
        json=inspection({"front_kg": [108, "108", 108]}),
    ),
    "a string wheelbase": Bad(
        "POST",
        VEHICLES,
        422,
        "wheelbase_m",
        "number_type",
        ("wheelbase_m", "JSON number"),
        json=vehicle(wheelbase_m="1.95"),
    ),
    "a number where the registration is required": Bad(
        "POST",
        INSPECTIONS,
        422,
        "registration_number",
        "string_type",
        ("registration_number", "string"),
        json=inspection(registration_number=252),
    ),
    "a seat that is not an object": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[1]",
        "model_attributes_type",
        ("seats[1]",),
        json=vehicle(seats=[{"role": "driver", "x_m": 0.9}, 1.6]),
    ),
    # NaN and Infinity (Python's json reads them, so they reach the validators)
    "NaN as a weight": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg",
        "finite_number",
        ("readings.front_kg", "finite"),
        content=raw(json.dumps(inspection({"front_kg": float("nan")}))),
    ),
    "Infinity as the overall weight": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.overall_kg",
        "finite_number",
        ("readings.overall_kg", "finite"),
        content=raw(json.dumps(inspection({"overall_kg": float("inf")}))),
    ),
    "-Infinity among repeated readings": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.left_rear_kg[1]",
        "finite_number",
        ("finite",),
        content=raw(json.dumps(inspection({"left_rear_kg": [115, float("-inf")]}))),
    ),
    "NaN as a seat position": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[0].x_m",
        "finite_number",
        ("seats[0].x_m", "finite"),
        content=raw(json.dumps(vehicle(seats=[{"role": "driver", "x_m": float("nan")}]))),
    ),
    "NaN as the occupant mass": Bad(
        "POST",
        INSPECTIONS,
        422,
        "occupants.mass_kg",
        "finite_number",
        ("occupants.mass_kg", "finite"),
        content=raw(json.dumps(inspection(occupants={"mass_kg": float("nan")}))),
    ),
    # Weights that cannot be
    "a negative weight": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg",
        "greater_than",
        ("readings.front_kg", "greater than 0"),
        json=inspection({"front_kg": -108}),
    ),
    "a zero weight": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.right_rear_kg",
        "greater_than",
        ("greater than 0",),
        json=inspection({"right_rear_kg": 0}),
    ),
    "an absurd wheel weight (50 t)": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.left_rear_kg",
        "less_than_equal",
        ("readings.left_rear_kg", "1500"),
        json=inspection({"left_rear_kg": 50000}),
    ),
    "an absurd overall weight (50 t)": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.overall_kg",
        "less_than_equal",
        ("readings.overall_kg", "3000"),
        json=inspection({"overall_kg": 50000}),
    ),
    "an absurd occupant mass": Bad(
        "POST",
        INSPECTIONS,
        422,
        "occupants.mass_kg",
        "less_than_equal",
        ("occupants.mass_kg", "250"),
        json=inspection(occupants={"mass_kg": 5000}),
    ),
    "an implausible wheelbase": Bad(
        "POST",
        VEHICLES,
        422,
        "wheelbase_m",
        "greater_than_equal",
        ("wheelbase_m", "1"),
        json=vehicle(wheelbase_m=0.5),
    ),
    # Reading lists
    "an empty reading list": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg",
        "too_short",
        ("readings.front_kg", "at least 1"),
        json=inspection({"front_kg": []}),
    ),
    "more repeated readings than accepted": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg",
        "too_long",
        ("readings.front_kg", "20"),
        json=inspection({"front_kg": [108] * 21}),
    ),
    "a missing wheel": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.right_rear_kg",
        "missing",
        ("readings.right_rear_kg", "required"),
        json={"registration_number": "BDG 252 QH", "readings": {"front_kg": 108, "left_rear_kg": 115}},
    ),
    # Precision
    "a weight to too many decimal places": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.front_kg",
        "precision",
        ("readings.front_kg", "3 decimal places"),
        json=inspection({"front_kg": 108.1234, "overall_kg": None}),
    ),
    "a seat position to too many decimal places": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[0].x_m",
        "precision",
        ("seats[0].x_m", "4 decimal places"),
        json=vehicle(seats=[{"role": "driver", "x_m": 0.93031}]),
    ),
    # The paper's check: the wheel sum against the overall weight (tolerance 1 % of W)
    "a wheel sum 5.8 % off the overall weight": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.overall_kg",
        "sum_tolerance",
        ("readings.overall_kg", "358 kg", "380 kg", "1 %"),
        json=inspection({"overall_kg": 380}),
    ),
    "averaged wheels 1.2 % off the averaged overall weight": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.overall_kg",
        "sum_tolerance",
        ("358 kg", "362.3 kg"),
        json=inspection({"front_kg": [107, 109], "overall_kg": [362, 362.5, 362.5]}),
    ),
    "a measured case whose sum disagrees": Bad(
        "POST",
        INSPECTIONS,
        422,
        "measured_cases[0].readings.overall_kg",
        "sum_tolerance",
        ("measured_cases[0].readings.overall_kg", "431 kg", "450 kg"),
        json=inspection(
            measured_cases=[
                {
                    "occupants": 1,
                    "readings": {
                        "front_kg": 147,
                        "left_rear_kg": 134,
                        "right_rear_kg": 150,
                        "overall_kg": 450,
                    },
                }
            ]
        ),
    ),
    # Vehicles that are not on file, or are already
    "a submission for an unregistered vehicle": Bad(
        "POST",
        INSPECTIONS,
        404,
        "registration_number",
        "registered",
        ("registration_number", "no vehicle XYZ 999 is registered", "register it first"),
        json=inspection(registration_number="xyz-999"),
    ),
    "a registration already on file": Bad(
        "POST",
        VEHICLES,
        409,
        "registration_number",
        "unique",
        ("BDG 252 QH is already registered",),
        json=vehicle(registration_number="BDG 252 QH"),
    ),
    "a registration on file written differently (bdg-252qh)": Bad(
        "POST",
        VEHICLES,
        409,
        "registration_number",
        "unique",
        ("BDG 252QH (as BDG 252 QH) is already registered",),
        json=vehicle(registration_number="bdg-252qh"),
    ),
    "a registration that is not letters and digits": Bad(
        "POST",
        VEHICLES,
        422,
        "registration_number",
        "format",
        ("registration_number", "2 to 16 letters and digits"),
        json=vehicle(registration_number="KTU/417_XA"),
    ),
    "a control character in the make": Bad(
        "POST",
        VEHICLES,
        422,
        "make",
        "control_character",
        ("make", "U+0000"),
        json=vehicle(make="TVS\u0000"),
    ),
    "a blank model": Bad(
        "POST",
        VEHICLES,
        422,
        "model",
        "required",
        ("model", "blank"),
        json=vehicle(model="   "),
    ),
    # Unknown fields
    "an unknown field at the top level": Bad(
        "POST",
        INSPECTIONS,
        422,
        "colour",
        "extra_forbidden",
        ("colour", "not part of the API"),
        json=inspection(colour="green"),
    ),
    "an unknown field in the readings": Bad(
        "POST",
        INSPECTIONS,
        422,
        "readings.rear_kg",
        "extra_forbidden",
        ("readings.rear_kg",),
        json=inspection({"rear_kg": 250}),
    ),
    "an unknown field in a seat": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[1].mass_kg",
        "extra_forbidden",
        ("seats[1].mass_kg",),
        json=vehicle(
            seats=[{"role": "driver", "x_m": 0.9}, {"role": "passenger", "x_m": 1.6, "mass_kg": 72}]
        ),
    ),
    "a misspelt field in the occupants": Bad(
        "POST",
        INSPECTIONS,
        422,
        "occupants.mass",
        "extra_forbidden",
        ("occupants.mass",),
        json=inspection(occupants={"mass": 80}),
    ),
    # Bodies over 1 MiB (413), declared by Content-Length
    "a body over 1 MiB": Bad(
        "POST",
        INSPECTIONS,
        413,
        "body",
        "max_size",
        ("body", "1 MiB"),
        content=raw(json.dumps(inspection(note="x" * MIB))),
    ),
    # Seat layouts and loading configurations
    "a seat layout without the driver first": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[0].role",
        "driver_first",
        ("seats[0].role", "driver"),
        json=vehicle(seats=[{"role": "passenger", "x_m": 1.6}, {"role": "driver", "x_m": 0.9}]),
    ),
    "a seat layout with two drivers": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[1].role",
        "driver_first",
        ("seats[1].role",),
        json=vehicle(seats=[{"role": "driver", "x_m": 0.9}, {"role": "driver", "x_m": 1.6}]),
    ),
    "an unknown seat role": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[0].role",
        "literal_error",
        ("seats[0].role", "driver"),
        json=vehicle(seats=[{"role": "conductor", "x_m": 0.9}]),
    ),
    "occupants seated without the driver first": Bad(
        "POST",
        INSPECTIONS,
        422,
        "occupants.seats[0].role",
        "driver_first",
        ("occupants.seats[0].role",),
        json=inspection(occupants={"seats": [{"role": "passenger", "x_m": 1.6303}]}),
    ),
    "a seat out of reach of the wheelbase": Bad(
        "POST",
        VEHICLES,
        422,
        "seats[1].x_m",
        "range",
        ("seats[1].x_m", "2.95"),
        json=vehicle(seats=[{"role": "driver", "x_m": 0.9}, {"role": "passenger", "x_m": 3.5}]),
    ),
    "a load that would lift the front wheel": Bad(
        "POST",
        INSPECTIONS,
        422,
        "occupants.seats[0].x_m",
        "front_wheel_lift",
        ("occupants.seats[0].x_m", "front wheel", "lift off"),
        json=inspection(
            {"front_kg": 10, "left_rear_kg": 175, "right_rear_kg": 175, "overall_kg": None},
            occupants={"mass_kg": 250, "seats": [{"role": "driver", "x_m": 3.0}]},
        ),
    ),
    "a measured case with more occupants than seats": Bad(
        "POST",
        INSPECTIONS,
        422,
        "measured_cases[0].occupants",
        "range",
        ("measured_cases[0].occupants", "4"),
        json=inspection(measured_cases=[{"occupants": 5, "readings": STUDY_READINGS}]),
    ),
    # Reads of what is not on file
    "GET an unknown vehicle": Bad(
        "GET",
        f"{VEHICLES}/XYZ%20999",
        404,
        "registration_number",
        "registered",
        ("no vehicle XYZ 999 is registered",),
    ),
    "GET an unknown inspection": Bad(
        "GET",
        f"{INSPECTIONS}/999999",
        404,
        "inspection_id",
        "exists",
        ("inspection 999999 does not exist",),
    ),
    "GET an inspection id that is not a number": Bad(
        "GET",
        f"{INSPECTIONS}/first",
        422,
        "inspection_id",
        "int_parsing",
        ("inspection_id",),
    ),
    # Bad query parameters of the list
    "limit=0": Bad("GET", f"{INSPECTIONS}?limit=0", 422, "limit", "greater_than_equal", ("limit", "1")),
    "limit=100000": Bad("GET", f"{INSPECTIONS}?limit=100000", 422, "limit", "less_than_equal", ("500",)),
    "offset=-1": Bad("GET", f"{INSPECTIONS}?offset=-1", 422, "offset", "greater_than_equal", ("offset",)),
    "compliant=maybe": Bad(
        "GET",
        f"{INSPECTIONS}?compliant=maybe",
        422,
        "compliant",
        "bool_parsing",
        ("compliant",),
    ),
    "since=notadate": Bad(
        "GET",
        f"{INSPECTIONS}?since=notadate",
        422,
        "since",
        "datetime_format",
        ("since", "RFC 3339"),
    ),
    "since without a time zone": Bad(
        "GET",
        f"{INSPECTIONS}?since=2026-11-23T10:00:00",
        422,
        "since",
        "datetime_format",
        ("time zone",),
    ),
    "since a Unix time": Bad(
        "GET",
        f"{INSPECTIONS}?since=1700000000",
        422,
        "since",
        "datetime_format",
        ("since",),
    ),
    "until a day that does not exist": Bad(
        "GET",
        f"{INSPECTIONS}?until=2026-02-29T00:00:00Z",
        422,
        "until",
        "datetime_format",
        ("2026-02-29",),
    ),
    # Paths and methods that do not exist
    "DELETE an inspection": Bad(
        "DELETE",
        f"{INSPECTIONS}/1",
        405,
        "method",
        "method_not_allowed",
        ("DELETE", "GET"),
    ),
    "an unknown path": Bad(
        "GET",
        "/api/v1/no-such-thing",
        404,
        "path",
        "not_found",
        ("/api/v1/no-such-thing",),
    ),
}


def stored(session: Session) -> dict[str, int]:
    """Rows in each table, read in a fresh transaction (so rows committed by the app are seen)."""
    session.rollback()
    tables = Base.metadata.tables
    return {name: session.scalar(select(func.count()).select_from(tables[name])) or 0 for name in TABLES}


@pytest.fixture
def on_file(api: TestClient, session: Session) -> dict[str, int]:
    """The study's vehicle and one inspection of it on file; the row counts that follow."""
    assert api.post(VEHICLES, json=STUDY_VEHICLE).status_code == 201
    assert api.post(INSPECTIONS, json=inspection()).status_code == 201
    return stored(session)


def test_the_row_count_sees_what_the_api_stores(api: TestClient, session: Session) -> None:
    """The control for every refusal below: an accepted request does change the counts."""
    before = stored(session)
    assert api.post(VEHICLES, json=STUDY_VEHICLE).status_code == 201
    assert api.post(INSPECTIONS, json=inspection({"front_kg": [108, 108]})).status_code == 201
    after = stored(session)
    assert after == {
        "vehicle": before["vehicle"] + 1,
        "seat": before["seat"] + 4,
        "inspection": before["inspection"] + 1,
        "reading": before["reading"] + 5,
        "loading_case": before["loading_case"] + 5,
    }


@pytest.mark.parametrize("bad", BAD.values(), ids=BAD.keys())
def test_bad_input_is_refused_with_its_field_and_rule_and_nothing_is_stored(
    bad: Bad, api: TestClient, session: Session, on_file: dict[str, int]
) -> None:
    headers = dict(bad.headers)
    if not bad.signed:
        api.headers.pop("Authorization")
    if bad.content is not None:
        headers.setdefault("Content-Type", "application/json")
    response = api.request(bad.method, bad.path, json=bad.json, content=bad.content, headers=headers)

    assert response.status_code == bad.status, response.text
    if bad.status == 413:  # refused on the declared length (the streamed case is tested below)
        assert int(response.request.headers["content-length"]) > MIB
    assert response.headers["content-type"] == "application/json"
    body = response.json()
    assert set(body) == {"detail", "errors"}
    problems = {(p["field"], p["rule"]): p["message"] for p in body["errors"]}
    assert (bad.field, bad.rule) in problems, body
    message = problems[(bad.field, bad.rule)]
    assert message.startswith(f"{bad.field}:"), message
    for word in bad.words:
        assert word in message, message
    assert message in body["detail"]
    assert stored(session) == on_file


def test_401_tells_the_client_how_to_authenticate(client: TestClient) -> None:
    response = client.get(INSPECTIONS)
    assert response.status_code == 401
    assert response.headers["WWW-Authenticate"] == "Bearer"


def test_405_lists_every_method_of_the_path(api: TestClient) -> None:
    response = api.delete(INSPECTIONS)
    assert response.status_code == 405
    assert response.headers["Allow"] == "GET, POST"


def _chunks(total: int, size: int = 64 * 1024) -> Iterator[bytes]:
    yield b'{"registration_number": "BDG 252 QH", "note": "'
    for _ in range(total // size + 1):
        yield b"x" * size
    yield b'"}'


def test_a_streamed_body_over_1_mib_is_refused_without_a_content_length(
    api: TestClient, session: Session, on_file: dict[str, int]
) -> None:
    response = api.post(INSPECTIONS, content=_chunks(MIB), headers={"Content-Type": "application/json"})

    assert "content-length" not in response.request.headers
    assert response.request.headers["transfer-encoding"] == "chunked"
    assert response.status_code == 413
    message = "body: the request body is larger than the 1 MiB limit"
    assert response.json()["errors"] == [{"field": "body", "rule": "max_size", "message": message}]
    assert stored(session) == on_file


def test_a_streamed_body_under_the_limit_is_read_in_full(api: TestClient, on_file: dict[str, int]) -> None:
    body = json.dumps(inspection()).encode()
    response = api.post(
        INSPECTIONS, content=iter([body[:10], body[10:]]), headers={"Content-Type": "application/json"}
    )
    assert response.status_code == 201, response.text
