"""The station API keeps the promises of its OpenAPI schema: schemathesis runs every check it has.

Every operation is exercised with schema-valid (positive) and schema-violating (negative) requests
in the examples, coverage and fuzzing phases, signed with a real station key, with the study's
vehicle and one inspection of it on file (and a second vehicle of its model, so that a type
assessment can succeed) so that submissions and reads can succeed. Every check
schemathesis registers runs (not_a_server_error, status_code_conformance, content_type_conformance,
response_schema_conformance, response_headers_conformance, negative_data_rejection,
missing_required_header, unsupported_method, allow_header_conformance, ignored_auth, ...), and a
stateful run follows the links schemathesis infers (a stored inspection to its read and certificate,
a certificate to its PDF), where the stateful checks (use_after_free, ensure_resource_availability,
object_level_authorization) act too. One is narrowed, not disabled: positive_data_acceptance
also accepts a 422 for a rule that relates several fields, which JSON Schema cannot state, once the
request is shown to break it (see `refused_by_a_cross_field_rule`) and the operation's description
in the schema names that rule (`documented_in_the_schema`, app/api/cross_field.py), a remedies query
beyond the stored inspection's seats or wheelbase (`refused_for_the_inspection_on_file`, documented
the same way), or a 422 for an
Idempotency-Key that this run sent before with another request; in the stateful run negative_data_rejection is
narrowed the same way for one schemathesis artefact (a linked path value judged while still
percent-encoded, see `negative_data_rejection_with_linked_values_decoded`). Checks are added: the
narrowed ones, and one that the station key is honoured, without which a key that never reached
the app would pass everything (401 is an accepted answer to any request). The station's rate limit,
the throttle of invalid keys per address and the public verification's limit are lifted for the run
(it floods one key, and sends invalid ones, on purpose; tests/stations and tests/certificates test
the limits).

The run is deterministic (fixed seed, derandomized Hypothesis) and bounded (40 examples per
operation and phase; 30 stateful runs of up to 8 steps), so it is the same test on every CI run.
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Iterator
from decimal import Decimal
from fractions import Fraction
from typing import Any
from urllib.parse import unquote

import pytest
import schemathesis
from emptied import empty_every_table
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from schemathesis.checks import CheckContext
from schemathesis.core.failures import Failure
from schemathesis.core.parameters import ParameterLocation
from schemathesis.generation import GenerationMode
from schemathesis.generation.meta import TestPhase
from schemathesis.specs.openapi.checks import negative_data_rejection, positive_data_acceptance
from sqlalchemy import Engine, select
from sqlalchemy.orm import Session
from study_data import STUDY_VEHICLE

from app import config
from app.db import get_sessionmaker
from app.inspections.models import Inspection
from app.main import create_app
from app.stability import Rules
from app.stations.models import Station
from app.stations.scale import ScaleRules
from app.stations.service import hash_key, new_key
from app.vehicles.models import Vehicle

STUDY_INSPECTION: dict[str, Any] = {
    "registration_number": "bdg-252qh",
    "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
}
RULES = Rules()
SCALE = ScaleRules()

# A station key made for this run; the `on_file` fixture stores its hash as a station. Schemathesis signs
# every request with it through the schema's HTTPBearer scheme, except the requests in which it
# deliberately leaves the key out (those must answer 401).
STATION_KEY = new_key()
# Examples per operation and phase; raise it for a deeper search than CI's (it stays deterministic).
EXAMPLES = int(os.environ.get("TRIKECERT_SCHEMATHESIS_EXAMPLES", "40"))
CONFIG = schemathesis.Config.from_dict(
    {
        "seed": 20261123,
        "generation": {"max-examples": EXAMPLES, "deterministic": True},
        "auth": {"openapi": {"HTTPBearer": {"bearer": STATION_KEY}}},
    }
)
# The schema is read from an app built at import; every request goes to the app of the `client`
# fixture, which is built once the test database is in place.
schema = schemathesis.openapi.from_asgi("/openapi.json", create_app(), config=CONFIG)
SCHEMA_DOCUMENT: dict[str, Any] = create_app().openapi()


# The inspection the `on_file` fixture stored for the running test, and the second vehicle's.
ON_FILE: dict[str, int] = {"inspection_id": 1, "second_inspection_id": 2}
SECOND_VEHICLE = {**STUDY_VEHICLE, "registration_number": "AGL 7180"}
SECOND_INSPECTION: dict[str, Any] = {
    "registration_number": "AGL 7180",
    "readings": {"front_kg": 110, "left_rear_kg": 116, "right_rear_kg": 133, "overall_kg": 360},
}


def _aim_at_records_on_file(case: schemathesis.Case[Any], choice: int) -> None:
    """Point a schema-valid request at the vehicle or inspection on file (choice 1 and 2 vary how)."""
    operation = f"{case.operation.method.upper()} {case.operation.path}"
    registration = str(STUDY_VEHICLE["registration_number"])
    if operation == "POST /api/v1/inspections" and isinstance(case.body, dict):
        body: dict[str, Any] = copy.deepcopy(case.body)
        body["registration_number"] = registration
        if choice == 2:  # no overall weight: the wheel sum is the total, nothing to disagree with
            body["readings"].pop("overall_kg", None)
        case.body = body
    elif operation == "GET /api/v1/vehicles/{registration_number}":
        case.path_parameters = {"registration_number": registration if choice == 1 else "bdg-252qh"}
    elif operation in (
        "GET /api/v1/inspections/{inspection_id}",
        "GET /api/v1/inspections/{inspection_id}/remedies",
    ):
        case.path_parameters = {"inspection_id": ON_FILE["inspection_id"]}
    elif operation == "POST /api/v1/type-assessments" and isinstance(case.body, dict):
        body = {**case.body, "make": STUDY_VEHICLE["make"], "model": STUDY_VEHICLE["model"]}
        body.pop("model_year", None)
        body.pop("inspection_ids", None)
        if choice == 2:  # the two inspections on file, chosen
            body["inspection_ids"] = [ON_FILE["inspection_id"], ON_FILE["second_inspection_id"]]
        case.body = body
    elif operation == "GET /api/v1/inspections":
        case.query = {**case.query, "registration_number": registration if choice == 1 else "bdg-252qh"}


@schema.hook
def flatmap_case(context: schemathesis.HookContext, case: schemathesis.Case[Any]) -> st.SearchStrategy[Any]:
    """Aim two thirds of the schema-valid requests at the records on file.

    Random registrations and ids are almost never on file (404), and a random overall weight almost
    never agrees with the wheel sum, so without this the assessment and the 200 answers would rarely
    be exercised. Only positive cases are changed, and they stay schema-valid.
    """
    if case.meta is None or case.meta.generation.mode != GenerationMode.POSITIVE:
        return st.just(case)
    generated = (copy.deepcopy(case.body), dict(case.path_parameters), dict(case.query))

    def aim(choice: int) -> schemathesis.Case[Any]:
        case.body, case.path_parameters, case.query = copy.deepcopy(generated)
        if choice:
            _aim_at_records_on_file(case, choice)
        return case

    return st.sampled_from([0, 1, 2]).map(aim)


def _at(body: dict[str, Any], field: str) -> Any:
    """The value an error's `field` path (`measured_cases[0].readings.front_kg`) names in the body."""
    node: Any = body
    for part in field.replace("]", "").replace("[", ".").split("."):
        node = node[int(part)] if part.isdigit() else node[part]
    return node


def _decimal(value: Any) -> Fraction:
    return Fraction(Decimal(str(value)))


def _mean(value: Any) -> Fraction:
    values = value if isinstance(value, list) else [value]
    return sum((_decimal(v) for v in values), Fraction(0)) / len(values)


def _sum_disagrees(readings: dict[str, Any]) -> bool:
    overall = readings.get("overall_kg")
    if overall is None:
        return False
    wheels = sum(
        _mean(value) for wheel, value in readings.items() if wheel != "overall_kg" and value is not None
    )
    return abs(wheels - _mean(overall)) > Fraction(RULES.sum_tolerance) * _mean(overall)


def _beyond_reach(body: dict[str, Any], field: str) -> bool:
    """Is the position at `field` (seats[i].x_m, occupants.seats[i].x_m, load_items[i].x_m) out of reach?"""
    wheelbase = _decimal(body.get("wheelbase_m") or STUDY_VEHICLE["wheelbase_m"])
    return _decimal(_at(body, field)) > wheelbase + Fraction(RULES.seat_reach_m)


def _seat_count(body: dict[str, Any]) -> int:
    occupants = body.get("occupants") or {}
    return len(occupants.get("seats") or STUDY_VEHICLE["seats"])


def refused_by_a_cross_field_rule(body: dict[str, Any], problem: dict[str, str]) -> bool:
    """Is this refusal one that JSON Schema cannot express, and does the request really break it?

    JSON Schema constrains each value on its own. These domain rules relate several values, so a
    request can satisfy the schema and still be refused (422), and the refusal is right:
    - the wheel sum against the overall weight (sum_tolerance, recomputed here);
    - the wheels read against the vehicle's axle layout (missing, extra_forbidden: the study vehicle is
      a delta);
    - a seat or load position against the wheelbase, which may come from the body or the vehicle
      (range on an `x_m`, recomputed here);
    - a measured case against the number of seats (range on measured_cases[i].occupants,
      recomputed here) or measured twice (duplicate);
    - a loading case that would lift the front or rear wheels (the study's moment arithmetic over
      readings, seats, masses and wheelbase together);
    - a type assessment's model against the records on file: fewer than two vehicles, an inspection
      of another model or of a vehicle named twice, different seat layouts (checked in the database).
    - the axle-lift weighing for the estimates: the raised front reading not below the level one
      (less_than_level), a lift not below the wheelbase (below_wheelbase), or both a lift and a CG
      height given (one_of), each recomputed here; a front track for a vehicle with one front wheel
      (front_track).
    """
    field, rule = problem.get("field", ""), problem.get("rule", "")
    if rule in ("missing", "extra_forbidden") and field.split(".")[-2:-1] == ["readings"]:
        # The vehicle's axle layout decides its wheels; the study vehicle is a delta.
        readings = _at(body, field.rsplit(".", 1)[0])
        given = {wheel for wheel, value in readings.items() if wheel != "overall_kg" and value is not None}
        return given != {"front_kg", "left_rear_kg", "right_rear_kg"}
    if rule == "sum_tolerance":
        return _sum_disagrees(_at(body, field.removesuffix(".overall_kg")))
    if rule == "range" and field.endswith("x_m"):
        return _beyond_reach(body, field)
    if rule == "range" and field.startswith("measured_cases[") and field.endswith("].occupants"):
        index = int(field.removeprefix("measured_cases[").removesuffix("].occupants"))
        return bool(body["measured_cases"][index]["occupants"] > _seat_count(body))
    if rule == "duplicate" and field.startswith("measured_cases["):
        counts = [case["occupants"] for case in body.get("measured_cases", [])]
        return len(counts) != len(set(counts))
    if rule == "spread":  # repeated readings of one wheel that disagree: the scale had not settled
        values = [_decimal(v) for v in _at(body, field)]
        return max(values) - min(values) > Fraction(SCALE.max_spread_kg)
    if rule in TYPE_RULES and "make" in body and "model" in body:
        return _type_refusal_explained(body, field, rule)
    if rule == "less_than_level":
        return _mean(body["cg_lift"]["front_kg"]) >= _mean(body["readings"]["front_kg"])
    if rule == "below_wheelbase":
        wheelbase = _decimal(body.get("wheelbase_m") or STUDY_VEHICLE["wheelbase_m"])
        return _decimal(body["cg_lift"]["lift_height_m"]) >= wheelbase
    if rule == "one_of":
        return body.get("cg_lift") is not None and body.get("cg_height_m") is not None
    if rule == "front_track":  # the body's layout, else the test's vehicle's: a delta
        return body.get("front_track_m") is not None and body.get("layout", "delta") == "delta"
    return rule in {"front_wheel_lift", "rear_wheel_lift"}


# A type assessment's refusals relate the request to the records on file (the run's station's).
TYPE_RULES = {"too_few", "same_model", "one_per_vehicle", "same_layout", "measured_cases"}


def _of_model(vehicle: Vehicle, body: dict[str, Any]) -> bool:
    year = body.get("model_year")
    return (
        vehicle.make.strip().lower() == body["make"].strip().lower()
        and vehicle.model.strip().lower() == body["model"].strip().lower()
        and (year is None or vehicle.model_year == year)
    )


def _type_refusal_explained(body: dict[str, Any], field: str, rule: str) -> bool:
    """Do the stored records really break the rule the type assessment was refused for?"""
    ids = body.get("inspection_ids")
    with get_sessionmaker()() as session:
        if ids is None:
            inspections = [
                i
                for i in session.scalars(select(Inspection).order_by(Inspection.id))
                if _of_model(i.vehicle, body)
            ]
            latest = {i.vehicle_id: i for i in inspections}  # the last of each vehicle, by id
            chosen = list(latest.values())
        else:
            chosen = [i for i in (session.get(Inspection, n) for n in ids) if i is not None]
        if rule == "too_few":
            return len(chosen) < 2
        index = (
            int(field.removeprefix("inspection_ids[").removesuffix("]")) if field != "inspection_ids" else 0
        )
        if rule == "same_model":
            return not _of_model(chosen[index].vehicle, body)
        if rule == "one_per_vehicle":
            return chosen[index].vehicle_id in {i.vehicle_id for i in chosen[:index]}
        if rule == "measured_cases":
            return any(r.case_occupants > 0 for i in chosen for r in i.readings)
        layouts = {
            (json.dumps(i.occupant_config, sort_keys=True), str(i.wheelbase_m), str(i.occupant_mass_kg))
            for i in chosen
        }
        return len(layouts) > 1


def refused_for_the_inspection_on_file(case: schemathesis.Case[Any], problem: dict[str, str]) -> bool:
    """Is a remedies query refused for what the stored inspection has, and does it really exceed it?

    The schema bounds the target occupancy by the most seats any vehicle may have and the ballast
    position by the longest wheelbase; the inspection's own seats and wheelbase bound them further
    (range on target_occupants or ballast_x_m, recomputed here from the stored inspection).
    """
    if not case.operation.path.endswith("/remedies") or problem.get("rule") != "range":
        return False
    with get_sessionmaker()() as db:
        inspection = db.get(Inspection, int(case.path_parameters["inspection_id"]))
        if inspection is None:
            return False
        seats, wheelbase = len(inspection.occupant_config["seats"]), inspection.wheelbase_m
    query = case.query or {}
    if problem.get("field") == "target_occupants":
        return int(query["target_occupants"]) > seats
    if problem.get("field") == "ballast_x_m":
        return _decimal(query["ballast_x_m"]) > Fraction(wheelbase + RULES.seat_reach_m)
    return False


# Every Idempotency-Key this run sent, with the requests it went with: a 422 for reusing a key is
# right only when the same key went earlier with another request.
KEYS_SENT: dict[str, set[str]] = {}


def _idempotency_key(case: schemathesis.Case[Any]) -> str | None:
    for name, value in (case.headers or {}).items():
        if name.lower() == "idempotency-key":
            text = str(value)
            return text[1:-1] if len(text) > 1 and text[0] == text[-1] == '"' else text
    return None


def _reused_key(case: schemathesis.Case[Any], problem: dict[str, str]) -> bool:
    key = _idempotency_key(case)
    if problem.get("rule") != "idempotency_key_reused" or key is None:
        return False
    request = json.dumps([case.operation.path, case.body], sort_keys=True, default=str)
    return bool(KEYS_SENT.get(key, set()) - {request})


def _note_key(case: schemathesis.Case[Any]) -> None:
    key = _idempotency_key(case)
    if key is not None:
        request = json.dumps([case.operation.path, case.body], sort_keys=True, default=str)
        KEYS_SENT.setdefault(key, set()).add(request)


def documented_in_the_schema(case: schemathesis.Case[Any], problem: dict[str, str]) -> bool:
    """Does the operation's description in /openapi.json name the rule the request was refused for?

    A client generated from the schema reads the rules that relate several values there
    (app/api/cross_field.py); a refusal for a rule the schema does not name would surprise it.
    """
    operation = SCHEMA_DOCUMENT["paths"][case.operation.path][case.operation.method.lower()]
    return f"- `{problem.get('rule', '')}`:" in operation.get("description", "")


def positive_data_acceptance_with_cross_field_rules(
    ctx: CheckContext, response: schemathesis.Response, case: schemathesis.Case[Any]
) -> bool | None:
    """The built-in positive_data_acceptance, except for a 422 that only a cross-field rule explains.

    Narrowed, not disabled: a schema-valid request refused for any other reason (a bound, a type,
    a precision the schema does not state) still fails, and so does a cross-field refusal whose
    condition the request does not actually meet.
    """
    try:
        return positive_data_acceptance(ctx, response, case)
    except Failure:
        if response.status_code != 422:
            raise
        problems = response.json().get("errors", [])
        body = case.body if isinstance(case.body, dict) else None
        explained = [
            (
                documented_in_the_schema(case, p)
                and (
                    (body is not None and refused_by_a_cross_field_rule(body, p))
                    or refused_for_the_inspection_on_file(case, p)
                )
            )
            or _reused_key(case, p)
            for p in problems
        ]
        if not problems or not all(explained):
            raise
        return None
    finally:
        _note_key(case)


def the_station_key_is_honoured(
    ctx: CheckContext, response: schemathesis.Response, case: schemathesis.Case[Any]
) -> bool | None:
    """A request signed with the run's station key is never refused as unauthenticated.

    Without this, a key that never reached the app would pass every other check: 401 is an
    accepted answer to any request.
    """
    sent = response.request.headers.get("Authorization")
    if sent == f"Bearer {STATION_KEY}" and response.status_code == 401:
        raise AssertionError(f"the station key was refused: {response.text}")
    return None


@pytest.fixture
def no_rate_limit(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """The rate limits lifted while the fuzzer floods one key, sends invalid ones from one address and
    verifies many numbers (tests/stations and tests/certificates test the limits)."""
    monkeypatch.setenv("TRIKECERT_STATION_RATE_LIMIT", "0")
    monkeypatch.setenv("TRIKECERT_BAD_KEY_LIMIT", "0")
    monkeypatch.setenv("TRIKECERT_PUBLIC_RATE_LIMIT", "0")
    config.get_settings.cache_clear()
    yield
    monkeypatch.undo()
    config.get_settings.cache_clear()


def put_on_file(client: TestClient, session: Session) -> None:
    """The run's station key, the study's vehicle and one inspection of it, and a second of its model."""
    session.add(Station(name="Schemathesis", key_hash=hash_key(STATION_KEY), key_prefix=STATION_KEY[:10]))
    session.commit()
    client.headers["Authorization"] = f"Bearer {STATION_KEY}"
    response = client.post("/api/v1/vehicles", json=STUDY_VEHICLE)
    assert response.status_code == 201, response.text
    response = client.post("/api/v1/inspections", json=STUDY_INSPECTION)
    assert response.status_code == 201, response.text
    ON_FILE["inspection_id"] = response.json()["id"]
    assert client.post("/api/v1/vehicles", json=SECOND_VEHICLE).status_code == 201
    response = client.post("/api/v1/inspections", json=SECOND_INSPECTION)
    assert response.status_code == 201, response.text
    ON_FILE["second_inspection_id"] = response.json()["id"]


@pytest.fixture
def on_file(client: TestClient, session: Session, no_rate_limit: None) -> None:
    """The records of `put_on_file`, for this test."""
    put_on_file(client, session)


@schema.parametrize()
@settings(deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@pytest.mark.usefixtures("on_file")
def test_the_api_conforms_to_its_openapi_schema(case: schemathesis.Case[Any], client: TestClient) -> None:
    case.call_and_validate(
        app=client.app,
        excluded_checks=[positive_data_acceptance],
        additional_checks=[positive_data_acceptance_with_cross_field_rules, the_station_key_is_honoured],
    )


def negative_data_rejection_with_linked_values_decoded(
    ctx: CheckContext, response: schemathesis.Response, case: schemathesis.Case[Any]
) -> bool | None:
    """The built-in negative_data_rejection, except for a linked path value judged before decoding.

    In the stateful phase schemathesis fills a path parameter from an earlier answer (`T JF D`, the
    registration of a vehicle just stored) percent-encoded, then judges the encoded text (`T%20JF%20D`)
    against the schema: the `%` makes a valid registration look schema-violating, and the server, which
    decodes it, rightly finds the vehicle. Narrowed, not disabled: only a stateful step whose sole
    negative part is its path is excused, and only when every path value, decoded, satisfies the schema.
    """
    try:
        return negative_data_rejection(ctx, response, case)
    except Failure:
        meta = case.meta
        if meta is None or meta.phase.name != TestPhase.STATEFUL:
            raise
        negative = [where for where, part in meta.components.items() if part.mode.is_negative]
        decoded = {name: unquote(str(value)) for name, value in (case.path_parameters or {}).items()}
        if negative != [ParameterLocation.PATH] or not decoded:
            raise
        if not case.operation.path_parameters.get_strict_validator().is_valid(decoded):
            raise
        return None


# The stateful phase: chains of calls along the links schemathesis infers from the schema (a stored
# inspection's id to its read and its certificate, a certificate's number to its read and its PDF).
# Only here do the stateful checks act: use_after_free, ensure_resource_availability and
# object_level_authorization, beside every other check.
APIWorkflow = schema.as_state_machine()


def _only_on_file(engine: Engine, client: TestClient) -> None:
    """Every table emptied (as the tables' owner), then the records of `put_on_file` stored again."""
    empty_every_table(engine)
    with get_sessionmaker()() as session:
        put_on_file(client, session)


@pytest.mark.usefixtures("no_rate_limit")
def test_linked_calls_keep_the_promises_of_the_schema(
    client: TestClient, engine: Engine, owner_engine: Engine
) -> None:
    class Workflow(APIWorkflow):  # type: ignore[misc,valid-type]
        def setup(self) -> None:
            # Each scenario starts from the same records: Hypothesis replays and shrinks scenarios, and
            # one that met the records another left behind would answer differently the second time.
            _only_on_file(owner_engine, client)  # the owner: the app may not empty the records

        def get_call_kwargs(self, case: schemathesis.Case[Any]) -> dict[str, Any]:
            return {"app": client.app}

        def validate_response(
            self,
            response: schemathesis.Response,
            case: schemathesis.Case[Any],
            additional_checks: list[Any] | None = None,
            **kwargs: Any,
        ) -> None:
            case.validate_response(
                response,
                excluded_checks=[positive_data_acceptance, negative_data_rejection],
                additional_checks=[
                    positive_data_acceptance_with_cross_field_rules,
                    negative_data_rejection_with_linked_values_decoded,
                    the_station_key_is_honoured,
                ],
                transport_kwargs=kwargs or None,
                recorder=self.recorder,
            )

    Workflow.run(
        settings=settings(
            max_examples=max(30, EXAMPLES // 2),
            stateful_step_count=8,
            derandomize=True,
            deadline=None,
            database=None,
            suppress_health_check=list(HealthCheck),
        )
    )
