"""Validate a body in the handler exactly as FastAPI would have: the same errors, at `body.<field>`."""

from __future__ import annotations

from typing import Any, TypeVar

from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, ValidationError

Model = TypeVar("Model", bound=BaseModel)


def validated_body(document: Any, model: type[Model]) -> Model:
    """The parsed JSON body as `model`; RequestValidationError (422 naming each field) otherwise."""
    if document is None:
        missing = {"type": "missing", "loc": ("body",), "msg": "Field required", "input": None}
        raise RequestValidationError([missing], body=document)
    try:
        return model.model_validate(document, from_attributes=True)
    except ValidationError as error:
        errors = [{**e, "loc": ("body", *e["loc"])} for e in error.errors(include_url=False)]
        raise RequestValidationError(errors, body=document) from None
