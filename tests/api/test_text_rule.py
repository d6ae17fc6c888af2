"""Every string of the station API, found from the app's own OpenAPI schema (so a new field is
covered without a new test), is sent with each kind of character the text rule refuses, and too long:
the answer is a 4xx naming the field and the rule, and no table gains a row. The same field with good
text (typed with combining accents) is accepted and stored composed (NFC), so the walk is not vacuous.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Iterator
from typing import Any
from urllib.parse import quote

import pytest
from fastapi.testclient import TestClient
from openapi_walk import SCHEMA, field_name, leaves, options, place, sample, send_json
from row_counts import rows_per_table
from sqlalchemy import Engine
from text_classes import INVISIBLE_CLASSES, named

from app.api.fields import TEXT_PATTERN

# One of each class the rule refuses, with the rule the API must name.
BAD_CHARACTERS: dict[str, tuple[str, str]] = {
    "NUL": ("\x00", "control_character"),
    "escape (C0)": ("\x1b", "control_character"),
    "line feed": ("\n", "control_character"),
    "delete": ("\x7f", "control_character"),
    "next line (C1)": ("\x85", "control_character"),
    "right-to-left override": ("\u202e", "bidi_control"),
    "left-to-right embedding": ("\u202a", "bidi_control"),
    "first strong isolate": ("\u2068", "bidi_control"),
    "right-to-left mark": ("\u200f", "bidi_control"),
    "Arabic letter mark": ("\u061c", "bidi_control"),
    "zero-width space": ("\u200b", "invisible_character"),
    "zero-width joiner": ("\u200d", "invisible_character"),
    "word joiner": ("\u2060", "invisible_character"),
    "byte-order mark": ("\ufeff", "invisible_character"),
    "unpaired surrogate": ("\ud800", "unpaired_surrogate"),
    "replacement character": ("\ufffd", "replacement_character"),
    **INVISIBLE_CLASSES,
}
DECOMPOSED = unicodedata.normalize("NFD", "Ṣàngó")  # S + dot below, a + grave, o + acute
VEHICLES = "/api/v1/vehicles"


def body_cases() -> Iterator[tuple[str, str, tuple[str | int, ...], dict[str, Any]]]:
    """(method, path, string path, body schema) of every string in every JSON request body."""
    for url, operations in SCHEMA["paths"].items():
        for method, operation in operations.items():
            content = operation.get("requestBody", {}).get("content", {}).get("application/json")
            if content:
                for leaf, _string in leaves(content["schema"], "string"):
                    yield method.upper(), url, leaf, content["schema"]


def parameter_cases() -> Iterator[tuple[str, str, str, str]]:
    """(method, path, where, name) of every string path or query parameter."""
    for url, operations in SCHEMA["paths"].items():
        for method, operation in operations.items():
            for parameter in operation.get("parameters", []):
                kinds = {o.get("type") for o in options(parameter["schema"])}
                if "string" in kinds and parameter["in"] in ("path", "query"):
                    yield method.upper(), url, parameter["in"], parameter["name"]


BODY_CASES = {f"{m} {u} {field_name(leaf)}": (m, u, leaf, s) for m, u, leaf, s in body_cases()}
PARAMETER_CASES = {f"{m} {u} {where} {name}": (m, u, where, name) for m, u, where, name in parameter_cases()}


def test_the_walk_finds_the_strings_of_the_api() -> None:
    """The walk reaches every kind of string the API takes, so a field missing here is a walk defect."""
    assert {"POST /api/v1/vehicles make", "POST /api/v1/inspections load_items[0].label"} <= set(BODY_CASES)
    assert "GET /api/v1/inspections query registration_number" in PARAMETER_CASES
    assert "GET /api/v1/vehicles/{registration_number} path registration_number" in PARAMETER_CASES


TYPE_ASSESSMENTS = "/api/v1/type-assessments"


def counts(engine: Engine) -> dict[str, int]:
    """Rows per table, except the station rate limit's window (every request counts in it)."""
    return rows_per_table(engine, leave_out={"station_rate_window"})


def prepare(api: TestClient, url: str) -> None:
    """The example vehicle on file, unless registering it is what the request under test does."""
    vehicle = SCHEMA["paths"][VEHICLES]["post"]["requestBody"]["content"]["application/json"]["schema"]
    if url != VEHICLES:
        assert send_json(api, "POST", VEHICLES, sample(vehicle)).status_code == 201


def good_text(string: dict[str, Any], current: Any) -> str:
    """Text the field must accept: a decomposed name for free text, the example for identifiers."""
    return DECOMPOSED if string.get("pattern") == TEXT_PATTERN else str(current)


def _string_schema(schema: dict[str, Any], leaf: tuple[str | int, ...]) -> dict[str, Any]:
    return dict(next(s for path, s in leaves(schema, "string") if path == leaf))


def _bodies(schema: dict[str, Any], leaf: tuple[str | int, ...]) -> tuple[Any, str]:
    """The operation's example body with the leaf present, and good text for the leaf."""
    body = sample(schema)
    current: Any = body
    for part in leaf:
        has = (isinstance(current, dict) and part in current) or (isinstance(current, list) and current)
        current = current[part] if has else None
    return place(body, schema, leaf, None), good_text(_string_schema(schema, leaf), current or "")


@pytest.mark.parametrize("case", BODY_CASES)
def test_good_text_in_every_string_of_a_body_is_accepted_and_stored_composed(
    api: TestClient, engine: Engine, case: str
) -> None:
    method, url, leaf, schema = BODY_CASES[case]
    prepare(api, url)
    base, good = _bodies(schema, leaf)
    assert good, f"no good text known for {case}"
    response = send_json(api, method, url, place(base, schema, leaf, good))
    if url == TYPE_ASSESSMENTS:  # the text passes; a model nobody has weighed has no vehicles to assess
        assert response.status_code == 422, response.text
        assert response.json()["errors"][0]["rule"] == "too_few"
    else:
        assert response.status_code == 201, response.text
    if good == DECOMPOSED:  # as stored (a chassis number is kept in upper case)
        composed = unicodedata.normalize("NFC", good)
        assert composed in response.text or composed.upper() in response.text
        assert good not in response.text
        assert good.upper() not in response.text


@pytest.mark.parametrize("case", BODY_CASES)
def test_a_refused_character_in_any_string_of_a_body_is_a_422_naming_field_rule_and_character(
    api: TestClient, engine: Engine, case: str
) -> None:
    """Each class of refused character in turn (one request each, the records prepared once)."""
    method, url, leaf, schema = BODY_CASES[case]
    prepare(api, url)
    base, good = _bodies(schema, leaf)
    for bad, (char, rule) in BAD_CHARACTERS.items():
        before = counts(engine)
        response = send_json(api, method, url, place(base, schema, leaf, good[:2] + char + good[2:]))
        assert response.status_code == 422, f"{bad}: {response.text}"
        problems = {(p["field"], p["rule"]) for p in response.json()["errors"]}
        assert (field_name(leaf), rule) in problems, f"{bad}: {response.text}"
        detail = response.json()["detail"]
        assert (named(char) if bad in INVISIBLE_CLASSES else f"U+{ord(char):04X}") in detail, detail
        assert counts(engine) == before, bad


def test_the_schema_s_pattern_refuses_what_the_rule_refuses_and_takes_what_it_takes() -> None:
    """A client that validates against /openapi.json is not surprised: the pattern and the rule agree."""
    pattern = re.compile(TEXT_PATTERN)
    for bad, (char, rule) in BAD_CHARACTERS.items():
        if rule != "unpaired_surrogate":  # no pattern can name one (app/api/fields.py)
            assert not pattern.search(f"Ba{char}jaj"), bad
    for good in ("Bajaj", DECOMPOSED, "Ṣàngó", "Keke 😀", "\U0001d400 bold", "Bajaj\u00a0RE", "ㄱ"):
        assert pattern.search(good), good


@pytest.mark.parametrize("case", BODY_CASES)
def test_text_longer_than_its_limit_is_refused_not_cut(api: TestClient, engine: Engine, case: str) -> None:
    method, url, leaf, schema = BODY_CASES[case]
    prepare(api, url)
    base, good = _bodies(schema, leaf)
    limit = _string_schema(schema, leaf)["maxLength"]
    before = counts(engine)
    response = send_json(api, method, url, place(base, schema, leaf, good + "A" * limit))
    assert response.status_code == 422, response.text
    problems = {(p["field"], p["rule"]) for p in response.json()["errors"]}
    assert (field_name(leaf), "max_length") in problems, response.text
    assert f"at most {limit} characters" in response.json()["detail"]
    assert counts(engine) == before


@pytest.mark.parametrize("case", PARAMETER_CASES)
def test_a_refused_character_in_any_path_or_query_parameter_is_a_4xx(
    api: TestClient, engine: Engine, case: str
) -> None:
    method, url, where, name = PARAMETER_CASES[case]
    prepare(api, "")
    for bad, (char, _rule) in BAD_CHARACTERS.items():
        # A surrogate cannot be written in UTF-8: a client can only send its would-be bytes.
        encoded = quote("BDG" + char + "252", encoding="utf-8", errors="surrogatepass")
        path = url
        for parameter in SCHEMA["paths"][url][method.lower()].get("parameters", []):
            if parameter["in"] == "path":
                value = encoded if parameter["name"] == name else "1"
                path = path.replace("{" + parameter["name"] + "}", value)
        if where == "query":
            path += f"?{name}={encoded}"
        before = counts(engine)
        response = api.request(method, path)
        assert 400 <= response.status_code < 500, f"{bad}: {response.text}"
        assert counts(engine) == before, bad
