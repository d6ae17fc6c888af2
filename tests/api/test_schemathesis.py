from __future__ import annotations

from typing import Any

import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from fastapi.testclient import TestClient

from app.main import create_app

APP = create_app()
CONFIG = schemathesis.Config.from_dict({
    "seed": 20261123,
    "generation": {"max-examples": 40, "deterministic": True},
})
schema = schemathesis.openapi.from_asgi("/openapi.json", APP, config=CONFIG)

VEHICLE = {
    "registration_number": "BDG 252 QH", "make": "Bajaj", "model": "RE", "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
}

@pytest.fixture
def key(api: TestClient) -> str:
    assert api.post("/api/v1/vehicles", json=VEHICLE).status_code == 201
    return api.headers["Authorization"]

@schema.parametrize()
@settings(deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_api(case: Any, key: str) -> None:
    case.call_and_validate(headers={"Authorization": key})
