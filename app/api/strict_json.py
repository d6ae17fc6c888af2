"""Strict JSON bodies for the station API: a key given twice in one object, a list longer than any
field takes, or a body of more objects than any request needs is refused (422, naming the field)
while the body is parsed, before Pydantic validates a single value.

Python's json keeps the last of two equal keys, so `{"front_kg": -5, "front_kg": 108}` would be
stored as 108 although the station sent -5 too; which one it meant cannot be known, so it is refused.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Coroutine
from typing import Any

from fastapi.routing import APIRoute
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import Response

from app.api.limits import MAX_LIST_ITEMS, MAX_OBJECTS
from app.errors import ServiceError


class JSONRefused(ServiceError, HTTPException):
    """A body refused while parsing (422).

    An HTTPException so FastAPI's body parsing lets it through, and a ServiceError so it is answered
    in the common error shape (the handler of the first of the two wins).
    """

    status = 422

    def __init__(self, message: str, *, field: str, rule: str) -> None:
        ServiceError.__init__(self, message, field=field, rule=rule)
        self.status_code = 422
        self.detail = message
        self.headers = None


class _Parsed(dict[str, Any]):
    """An object as parsed, remembering a key given twice and a list too long."""

    duplicate: str | None = None
    too_long: tuple[str, int] | None = None


def _repeated_key(pairs: list[tuple[str, Any]]) -> str:
    seen: set[str] = set()
    for key, _value in pairs:
        if key in seen:
            return key
        seen.add(key)
    raise AssertionError("no key is repeated")


def _pairs_hook() -> Callable[[list[tuple[str, Any]]], dict[str, Any]]:
    count = 0

    def build(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        nonlocal count
        count += 1
        if count > MAX_OBJECTS:  # refused at once: each object costs a call of this hook
            raise JSONRefused(
                f"body: the body holds more than {MAX_OBJECTS} JSON objects; no request needs that many",
                field="body",
                rule="max_objects",
            )
        parsed = _Parsed(pairs)
        if len(parsed) != len(pairs):
            parsed.duplicate = _repeated_key(pairs)
        for key, value in pairs:
            if isinstance(value, list) and len(value) > MAX_LIST_ITEMS:
                parsed.too_long = (key, len(value))
                break
        return parsed

    return build


def _join(path: str, part: str | int) -> str:
    if isinstance(part, int):
        return f"{path}[{part}]"
    return f"{path}.{part}" if path else part


def _first_problem(document: Any) -> tuple[str, _Parsed] | None:
    """The path of the first object (in document order) with a repeated key or a list too long."""
    stack: list[tuple[str, Any]] = [("", document)]
    while stack:
        path, node = stack.pop()
        if isinstance(node, _Parsed):
            if node.duplicate is not None or node.too_long is not None:
                return path, node
            children: list[tuple[str, Any]] = [(_join(path, k), v) for k, v in node.items()]
        elif isinstance(node, list) and len(node) <= MAX_LIST_ITEMS:
            children = [(_join(path, i), v) for i, v in enumerate(node)]
        else:
            continue
        stack.extend(child for child in reversed(children) if isinstance(child[1], dict | list))
    return None


def strict_loads(body: bytes | str) -> Any:
    """The JSON document, or JSONRefused for a repeated key, a list too long or too many objects.

    A malformed body raises json.JSONDecodeError, as json.loads does (FastAPI answers it with 400).
    """
    document = json.loads(body, object_pairs_hook=_pairs_hook())
    found = _first_problem(document)
    if found is None:
        return document
    path, node = found
    if node.duplicate is not None:
        field = _join(path, node.duplicate)
        raise JSONRefused(
            f"{field}: the key {node.duplicate!r} is given more than once in the same object; give it once",
            field=field,
            rule="duplicate_key",
        )
    assert node.too_long is not None
    key, length = node.too_long
    field = _join(path, key)
    raise JSONRefused(
        f"{field}: this list holds {length} values; no field of the API takes more than {MAX_LIST_ITEMS}",
        field=field,
        rule="too_long",
    )


class StrictJSONRequest(Request):
    """A request whose JSON body is read by `strict_loads`."""

    async def json(self) -> Any:
        """The body, parsed once, strictly."""
        if not hasattr(self, "_strict_json"):
            self._strict_json = strict_loads(await self.body())
        return self._strict_json


class StrictJSONRoute(APIRoute):
    """An API route whose JSON body is parsed strictly (use as an APIRouter's `route_class`)."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        """FastAPI's handler, given the strict request."""
        handler = super().get_route_handler()

        async def strict_handler(request: Request) -> Response:
            return await handler(StrictJSONRequest(request.scope, request.receive))

        return strict_handler
