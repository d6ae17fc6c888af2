"""The estimates beyond the static test in words, one function per fact (pages and PDF alike)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from decimal import Decimal

from app.web.formatting import fixed

SECTION_TITLE = "Beyond the static test (estimates, not part of the verdict)"
SECTION_LEAD = (
    "These figures rest on the inputs listed beside them, some of them assumed. They never change the "
    "verdict above, which is the study's static rule."
)
UNKNOWN = "Not known"
INPUT_WORDS = {
    "cg_lift or cg_height_m": "the centre of gravity height (a weighing with the front wheel raised)",
    "wheel_radius_m": "the loaded rear wheel radius",
    "track_m": "the rear track",
    "front_track_m": "the front track (two front wheels tip about it)",
    "front_cornering_stiffness_n_per_rad": "the front tyre's cornering stiffness",
    "rear_cornering_stiffness_n_per_rad": "the rear tyres' cornering stiffness",
    "drag_area_m2": "the drag area",
    "centre_of_pressure_height_m": "the centre of pressure height",
    "cg_height_m": "the centre of gravity height",
    "load_items heights": "the heights of the load items",
}
_SEAT = re.compile(r"seats\[(\d+)\]\.z_m")


def input_words(name: str) -> str:
    """One missing input in words: 'the rear track', 'the seated height on seat 2 (passenger 1)'."""
    seat = _SEAT.fullmatch(name)
    if seat:
        index = int(seat.group(1))
        return f"the seated height on {'the driver’s seat' if index == 0 else f'passenger seat {index}'}"
    return INPUT_WORDS.get(name, name)


def missing_sentence(missing: Sequence[str]) -> str | None:
    """Which inputs are not recorded, so which figures are blank; None when nothing is missing."""
    if not missing:
        return None
    return (
        "Not recorded, so the figures that need them are blank: "
        + "; ".join(input_words(m) for m in missing)
        + "."
    )


def figure_text(value: float | Decimal | None, places: int, unit: str = "") -> str:
    """A figure to `places` decimals with its unit, or 'Not known'."""
    if value is None:
        return UNKNOWN
    text = fixed(value, places)
    return f"{text}{unit}" if unit == "°" else f"{text} {unit}".strip()


def critical_speed_text(critical_kmh: float | None, margin: float | None) -> str:
    """'113.8 km/h', 'None (understeers)': stable at every speed, or 'Not known'."""
    if margin is None:
        return UNKNOWN
    if critical_kmh is None:
        return "None (understeers)"
    return figure_text(critical_kmh, 1, "km/h")


def readings_text(values: Sequence[str], mean_kg: float, places: int = 1) -> str:
    """The raised front wheel's reading(s): '94.8 kg', or '94.8 kg (mean of 94.8, 94.7, 94.9)'."""
    shown = figure_text(mean_kg, places, "kg")
    return shown if len(values) < 2 else f"{shown} (mean of {', '.join(values)})"
