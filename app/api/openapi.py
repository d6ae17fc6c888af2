"""A body the handler validates itself, after the key is checked and counted: FastAPI passes the parsed
JSON through untouched, while OpenAPI documents the model, generated as FastAPI would have.

    Body = Annotated[Any, PlainValidator(as_sent, json_schema_input_type=TheModel), fastapi.Body()]

with `= None` on the parameter, so that a missing body reaches the handler too (after the key), and
`REQUIRED_BODY` in the route's `openapi_extra` to document it as required.
"""

from __future__ import annotations

from typing import Any


def as_sent(document: Any) -> Any:
    """The parsed JSON, untouched (the handler validates it)."""
    return document


REQUIRED_BODY: dict[str, Any] = {"requestBody": {"required": True}}
