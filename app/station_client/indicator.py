"""A weighing indicator's serial output: lines like `ST,GS,+  108.0kg` (stable, gross) or
`US,GS,+  107.5kg` (unstable). Only stable positive weights are readings.

The operator weighs each wheel in turn (a delta's front, left rear, right rear; a tadpole's left
front, right front, rear; a quadricycle's left front, right front, left rear, right rear; then
optionally the whole vehicle), pressing PRINT on the indicator for each reading, `repeat` times per
wheel. An indicator in continuous mode sends a line many times a second: with `continuous`, a run of
identical stable lines is one reading, and the next reading of the same value needs an unstable or
empty-platform line in between.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from decimal import Decimal
from typing import Any

from app.station_client.files import LAYOUT_WHEELS, SourceError, Weighing, json_number

LINE = re.compile(
    r"^\s*(?P<state>ST|US|OL)\s*,\s*(?P<kind>GS|NT|GR)\s*,\s*(?P<sign>[+-])?\s*"
    r"(?P<value>\d+(?:\.\d+)?)\s*(?P<unit>kg|t)?\s*$",
    re.IGNORECASE,
)
UNIT_KG = {"kg": Decimal(1), "t": Decimal(1000)}
WHEELS = LAYOUT_WHEELS["delta"]


@dataclass(frozen=True)
class IndicatorLine:
    """One line of indicator output: stable or not, and the weight in kg (negative below zero)."""

    stable: bool
    kg: Decimal


def parse_line(text: str) -> IndicatorLine | None:
    """The line's state and weight, or None for anything that is not a weight line (overload too)."""
    match = LINE.match(text)
    if match is None or match["state"].upper() == "OL":
        return None
    kg = Decimal(match["value"]) * UNIT_KG[(match["unit"] or "kg").lower()]
    return IndicatorLine(stable=match["state"].upper() == "ST", kg=-kg if match["sign"] == "-" else kg)


def stable_readings(lines: Iterable[str], *, continuous: bool = False) -> Iterator[Decimal]:
    """The stable weights above zero, in order; in continuous mode one per settling of the scale."""
    last: Decimal | None = None
    for text in lines:
        line = parse_line(text)
        if line is None:
            continue
        if not line.stable or line.kg <= 0:
            last = None
            continue
        if continuous and line.kg == last:
            continue
        last = line.kg
        yield line.kg


def weighing_from_readings(
    registration_number: str,
    readings: Iterator[Decimal],
    *,
    repeat: int = 1,
    overall: bool = False,
    layout: str = "delta",
) -> Weighing:
    """One weighing: `repeat` readings of each of the layout's wheels in turn, then (with `overall`)
    the whole vehicle."""
    wheels = (*LAYOUT_WHEELS[layout], "overall_kg") if overall else LAYOUT_WHEELS[layout]
    body: dict[str, Any] = {"registration_number": registration_number, "readings": {}}
    for wheel in wheels:
        taken = [json_number(kg) for _, kg in zip(range(repeat), readings, strict=False)]
        if len(taken) < repeat:
            raise SourceError(
                f"the indicator gave too few stable readings: {wheel} needs {repeat}, got {len(taken)}; "
                "weigh again"
            )
        body["readings"][wheel] = taken[0] if repeat == 1 else taken
    return Weighing(body)
