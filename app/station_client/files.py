"""Weighings from files: a CSV with one weighing a row, or JSON holding the API's own bodies."""

from __future__ import annotations

import csv
import hashlib
import json
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from pathlib import Path
from typing import Any

# The wheels each axle layout is weighed on, in the order an operator goes round the vehicle (the
# service's own table is app/stability/layout.py; this program imports nothing of the service).
LAYOUT_WHEELS: dict[str, tuple[str, ...]] = {
    "delta": ("front_kg", "left_rear_kg", "right_rear_kg"),
    "tadpole": ("left_front_kg", "right_front_kg", "rear_kg"),
    "quadricycle": ("left_front_kg", "right_front_kg", "left_rear_kg", "right_rear_kg"),
}
WHEEL_COLUMNS = LAYOUT_WHEELS["delta"]
ALL_WHEEL_COLUMNS = (
    "front_kg",
    "left_front_kg",
    "right_front_kg",
    "left_rear_kg",
    "right_rear_kg",
    "rear_kg",
)
CSV_COLUMNS = ("registration_number", *WHEEL_COLUMNS, "overall_kg", "wheelbase_m")
CSV_ANY_COLUMNS = ("registration_number", *ALL_WHEEL_COLUMNS, "overall_kg", "wheelbase_m")


def _closest_layout(columns: list[str]) -> tuple[str, ...]:
    """The wheels of the layout the header holds most of (the delta first among equals)."""
    return max(LAYOUT_WHEELS.values(), key=lambda wheels: sum(w in columns for w in wheels))


class SourceError(Exception):
    """A weighing source that cannot be read; the message says where and what."""


@dataclass(frozen=True)
class Weighing:
    """One weighing to submit: the API body, and where it came from (so it is queued only once)."""

    body: dict[str, Any]
    source: str | None = None

    @property
    def registration_number(self) -> str:
        """The vehicle weighed, as written in the source."""
        return str(self.body.get("registration_number", ""))


def json_number(value: Decimal) -> int | float:
    """A decimal reading as a JSON number (readings have at most 3 decimals, which a float keeps)."""
    return int(value) if value == value.to_integral_value() else float(value)


def _source(path: Path, where: str, body: dict[str, Any]) -> str:
    digest = hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()[:16]
    return f"{path.resolve()}#{where}:{digest}"


def _numbers(cell: str, *, where: str) -> list[Decimal]:
    try:
        values = [Decimal(part) for part in cell.replace(";", " ").split()]
    except InvalidOperation as error:
        raise SourceError(
            f"{where}: {cell!r} is not a number of kg (repeated readings: 107;108;109)"
        ) from error
    if not all(value.is_finite() for value in values):
        raise SourceError(f"{where}: {cell!r} is not a finite number of kg")
    return values


def _reading(cell: str, *, where: str) -> int | float | list[int | float]:
    values = [json_number(v) for v in _numbers(cell, where=where)]
    if not values:
        raise SourceError(f"{where}: no reading given")
    return values[0] if len(values) == 1 else values


def read_csv(path: Path) -> list[Weighing]:
    """One weighing per row; a cell may hold repeated readings separated by `;` or spaces."""
    with path.open(newline="", encoding="utf-8-sig") as handle:
        reader = csv.DictReader(handle)
        columns = [c.strip() for c in reader.fieldnames or []]
        unknown = [c for c in columns if c not in CSV_ANY_COLUMNS]
        missing = [c for c in ("registration_number", *_closest_layout(columns)) if c not in columns]
        if unknown or missing:
            raise SourceError(
                f"{path}: columns must be {', '.join(CSV_COLUMNS)} (the last two optional); "
                f"unknown: {', '.join(unknown) or 'none'}; missing: {', '.join(missing) or 'none'}"
            )
        weighings = []
        for number, raw in enumerate(reader, start=2):
            row = {(k or "").strip(): (v or "").strip() for k, v in raw.items()}
            if not any(row.values()):
                continue
            where = f"{path}:{number}"
            body: dict[str, Any] = {"registration_number": row["registration_number"], "readings": {}}
            for column in (*ALL_WHEEL_COLUMNS, "overall_kg"):
                if row.get(column):
                    body["readings"][column] = _reading(row[column], where=f"{where} {column}")
            if row.get("wheelbase_m"):
                body["wheelbase_m"] = json_number(
                    _numbers(row["wheelbase_m"], where=f"{where} wheelbase_m")[0]
                )
            weighings.append(Weighing(body, _source(path, f"row{number}", body)))
    return weighings


def read_json(path: Path) -> list[Weighing]:
    """A list of API bodies (or `{"weighings": [...]}`, or one body), each sent as it is written."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as error:
        raise SourceError(f"{path}: not valid JSON ({error})") from error
    if isinstance(data, dict):
        data = data.get("weighings", [data])
    if not isinstance(data, list) or not all(isinstance(item, dict) for item in data):
        raise SourceError(f"{path}: give a list of weighings, each a JSON object like the API's body")
    weighings = []
    for index, body in enumerate(data):
        if "registration_number" not in body or "readings" not in body:
            raise SourceError(f"{path}: weighing {index} needs registration_number and readings")
        weighings.append(Weighing(body, _source(path, f"item{index}", body)))
    return weighings


def read_file(path: Path) -> list[Weighing]:
    """The weighings in a .csv or .json file."""
    if not path.is_file():
        raise SourceError(f"{path}: no such file")
    suffix = path.suffix.lower()
    try:
        if suffix == ".csv":
            return read_csv(path)
        if suffix == ".json":
            return read_json(path)
    except OSError as error:
        raise SourceError(f"{path}: cannot read ({error.strerror or error})") from error
    except UnicodeDecodeError as error:
        raise SourceError(f"{path}: not UTF-8 text (byte {error.start}); save it as UTF-8") from error
    except csv.Error as error:
        raise SourceError(f"{path}: not a readable CSV ({error})") from error
    raise SourceError(f"{path}: give a .csv or .json file (or read an indicator with `weigh`)")
