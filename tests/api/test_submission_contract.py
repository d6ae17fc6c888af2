"""POST /api/v1/inspections validates its body itself, after the station key is checked and counted:
its OpenAPI entry still documents the body, the key and the Idempotency-Key as FastAPI would, and a
refusal of the key comes before any refusal of the body."""

from __future__ import annotations

from fastapi.testclient import TestClient

INSPECTIONS = "/api/v1/inspections"


def test_the_openapi_entry_documents_the_body_the_key_and_the_idempotency_key(client: TestClient) -> None:
    document = client.get("/openapi.json").json()
    operation = document["paths"][INSPECTIONS]["post"]

    assert operation["requestBody"] == {
        "required": True,
        "content": {"application/json": {"schema": {"$ref": "#/components/schemas/InspectionIn"}}},
    }
    schema = document["components"]["schemas"]["InspectionIn"]
    assert schema["required"] == ["registration_number", "readings"]
    assert schema["additionalProperties"] is False
    assert operation["security"] == [{"HTTPBearer": []}]
    assert "HTTPBearer" in document["components"]["securitySchemes"]
    assert [p["name"] for p in operation["parameters"]] == ["Idempotency-Key"]


def test_a_missing_key_is_refused_before_the_body_is_looked_at(client: TestClient) -> None:
    response = client.post(INSPECTIONS, json={"readings": "not readings"})
    assert response.status_code == 401
    assert response.json()["errors"][0]["field"] == "Authorization"


def test_an_unknown_key_is_refused_before_the_body_is_looked_at(client: TestClient) -> None:
    headers = {"Authorization": "Bearer tks_not-a-key-of-any-station"}
    for body in ({"readings": "not readings"}, [1, 2, 3], None):
        response = client.post(INSPECTIONS, json=body, headers=headers)
        assert response.status_code == 401, (body, response.text)


def test_a_signed_request_without_a_body_is_told_to_send_one(api: TestClient) -> None:
    response = api.post(INSPECTIONS)
    assert response.status_code == 422
    assert response.json()["errors"] == [
        {
            "field": "body",
            "rule": "missing",
            "message": "body: send one JSON object, with Content-Type: application/json",
        }
    ]
