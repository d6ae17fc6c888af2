"""Walking the station API's own OpenAPI schema: the values a body may hold, a valid body to start
from, and a body with one value changed, so a test covers every field, present and future."""

from __future__ import annotations

import copy
import json
from collections.abc import Iterator
from typing import Any

from fastapi.testclient import TestClient
from httpx2 import Response

from app.main import create_app


def _schema() -> dict[str, Any]:
    schema: dict[str, Any] = create_app().openapi()
    return schema


SCHEMA = _schema()


def resolve(node: dict[str, Any]) -> dict[str, Any]:
    """A schema with its $ref followed."""
    while "$ref" in node:
        node = SCHEMA["components"]["schemas"][node["$ref"].rsplit("/", 1)[-1]]
    return node


def options(node: dict[str, Any]) -> list[dict[str, Any]]:
    node = resolve(node)
    for key in ("anyOf", "oneOf"):
        if key in node:
            return [resolve(o) for o in node[key] if resolve(o).get("type") != "null"]
    return [node]


def leaves(node: dict[str, Any], *kinds: str, path: tuple[str | int, ...] = ()) -> Iterator[tuple[Any, ...]]:
    """(path, schema) of every value of these JSON types a body may hold, arrays entered at index 0."""
    for option in options(node):
        kind = option.get("type")
        if kind in kinds:
            yield path, option
        elif kind == "object":
            for name, child in option.get("properties", {}).items():
                yield from leaves(child, *kinds, path=(*path, name))
        elif kind == "array":
            items = option.get("prefixItems", [option.get("items", {})])
            yield from leaves(items[0], *kinds, path=(*path, 0))


def sample(node: dict[str, Any]) -> Any:
    """A valid value of a schema: its example, const or default, or the simplest that fits."""
    node = resolve(node)
    if node.get("examples"):
        return copy.deepcopy(node["examples"][0])
    if "const" in node:
        return node["const"]
    if node.get("default") is not None:
        return copy.deepcopy(node["default"])
    option = options(node)[0]
    kind = option.get("type")
    if kind == "object":
        return {name: sample(option["properties"][name]) for name in option.get("required", [])}
    if kind == "array":
        return [sample(item) for item in option.get("prefixItems", [option.get("items", {})])]
    if kind in ("number", "integer"):
        low = option.get("minimum", option.get("exclusiveMinimum", 0))
        return round((low + option.get("maximum", low + 2)) / 2, 3)
    return "Bajaj"


def place(body: Any, node: dict[str, Any], path: tuple[str | int, ...], value: Any) -> Any:
    """`body` with `value` at `path`, missing parents made from the schema."""
    if not path:
        return value
    option = options(node)[0]
    head, rest = path[0], path[1:]
    if isinstance(head, int):
        items = option.get("prefixItems", [option.get("items", {})])
        body = body if isinstance(body, list) and body else [sample(items[0])]
        body[0] = place(body[0], items[0], rest, value)
        return body
    child = option["properties"][head]
    body = dict(body or {})
    body[head] = place(body.get(head, sample(child)), child, rest, value)
    return body


def field_name(path: tuple[str | int, ...]) -> str:
    """('load_items', 0, 'label') -> 'load_items[0].label', as the API names fields."""
    name = ""
    for part in path:
        name += f"[{part}]" if isinstance(part, int) else (f".{part}" if name else part)
    return name


def send_json(api: TestClient, method: str, url: str, body: Any) -> Response:
    """The body as JSON with \\u escapes, so an unpaired surrogate can be sent as a station could."""
    content = json.dumps(body).encode()
    response: Response = api.request(
        method, url, content=content, headers={"Content-Type": "application/json"}
    )
    return response
