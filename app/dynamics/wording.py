"""The estimates beyond the static test in words, one function per fact (pages and PDF alike)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from decimal import Decimal

from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.stability import DELTA, Layout
from app.web.formatting import fixed

SECTION_TITLE = N_("Beyond the static test (estimates, not part of the verdict)")
SECTION_LEAD = N_(
    "These figures rest on the inputs listed beside them, some of them assumed. They never change the "
    "verdict above, which is the study's static rule."
)
UNKNOWN = N_("Not known")
UNDERSTEERS = N_("None (understeers)")
MISSING = N_("Not recorded, so the figures that need them are blank: %(inputs)s.")
MEAN_OF = N_("%(reading)s (mean of %(readings)s)")
DRIVER_SEAT = N_("the seated height on the driver’s seat")
PASSENGER_SEAT = N_("the seated height on passenger seat %(seat)s")
INPUT_WORDS = {
    "cg_lift or cg_height_m": N_("the centre of gravity height (a weighing with the front wheel raised)"),
    "wheel_radius_m": N_("the loaded rear wheel radius"),
    "track_m": N_("the rear track"),
    "front_track_m": N_("the front track (two front wheels tip about it)"),
    "front_cornering_stiffness_n_per_rad": N_("the front tyre's cornering stiffness"),
    "rear_cornering_stiffness_n_per_rad": N_("the rear tyres' cornering stiffness"),
    "drag_area_m2": N_("the drag area"),
    "centre_of_pressure_height_m": N_("the centre of pressure height"),
    "cg_height_m": N_("the centre of gravity height"),
    "load_items heights": N_("the heights of the load items"),
}
# Where a layout's tyres are not the delta's one front and two rear, the words above would name the
# wrong ones: two front wheels are raised as an axle, one rear tyre is not "each".
TWO_FRONT_INPUT_WORDS = {
    "cg_lift or cg_height_m": N_("the centre of gravity height (a weighing with the front axle raised)"),
    "front_cornering_stiffness_n_per_rad": N_("each front tyre's cornering stiffness"),
}
ONE_REAR_INPUT_WORDS = {"rear_cornering_stiffness_n_per_rad": N_("the rear tyre's cornering stiffness")}
REVISION = N_("revision %(revision)s")
NONE_ON_FILE = N_("None on file")
NOT_RECORDED = N_("Not recorded")  # as every page words a gap (app/web/formatting.py)
_SEAT = re.compile(r"seats\[(\d+)\]\.z_m")


def section_title() -> str:
    """The section's title in the current language."""
    return _(SECTION_TITLE)


def section_lead() -> str:
    """What the section's figures rest on, in the current language."""
    return _(SECTION_LEAD)


def not_known() -> str:
    """'Not known' in the current language (a figure whose inputs are missing)."""
    return _(UNKNOWN)


def input_words(name: str, layout: Layout = DELTA) -> str:
    """One missing input in words: 'the rear track', 'the seated height on passenger seat 1'."""
    seat = _SEAT.fullmatch(name)
    if seat:
        index = int(seat.group(1))
        return _(DRIVER_SEAT) if index == 0 else _(PASSENGER_SEAT) % {"seat": index}
    words = {
        **INPUT_WORDS,
        **(TWO_FRONT_INPUT_WORDS if layout.n_front > 1 else {}),
        **(ONE_REAR_INPUT_WORDS if layout.n_rear == 1 else {}),
    }
    return _(words[name]) if name in words else name


def missing_sentence(missing: Sequence[str], layout: Layout = DELTA) -> str | None:
    """Which inputs are not recorded, so which figures are blank; None when nothing is missing."""
    if not missing:
        return None
    return _(MISSING) % {"inputs": "; ".join(input_words(m, layout) for m in missing)}


# The map's caption. The delta's words are the study's; other layouts name their limit, and what load
# moved rearward does to the rollover threshold differs (reference section 9).
DELTA_MAP_CAPTION = N_(
    "Each loading case at its LSF (across) and its estimated rollover threshold (up). Right of the dashed "
    "line at 2/3 a case is yaw-unstable. Moving load rearward raises one and worsens the other."
)
DELTA_MAP_CAPTION_WITH_MINIMUM = N_(
    "Each loading case at its LSF (across) and its estimated rollover threshold (up). Right of the dashed "
    "line at 2/3 a case is yaw-unstable; below the dotted line at the minimum rollover threshold it tips "
    "too easily. Moving load rearward raises one and worsens the other."
)
MAP_CAPTION = N_(
    "Each loading case at its LSF (across) and its estimated rollover threshold (up). Right of the dashed "
    "line at %(limit)s a case is yaw-unstable."
)
MAP_CAPTION_WITH_MINIMUM = N_(
    "Each loading case at its LSF (across) and its estimated rollover threshold (up). Right of the dashed "
    "line at %(limit)s a case is yaw-unstable; below the dotted line at the minimum rollover threshold it "
    "tips too easily."
)
ONE_REAR_REARWARD = N_(
    "Moving load rearward worsens both: with one rear wheel the rollover threshold falls as the LSF rises."
)
TWO_REAR_REARWARD = N_(
    "Moving load rearward worsens the LSF; it raises the rollover threshold only as far as the rear track "
    "is wider than the front track."
)


def map_caption(layout: Layout, *, with_minimum: bool) -> str:
    """What the stability map shows, against the layout's limit, and what load moved rearward does."""
    if layout == DELTA:  # the words the delta's pages have always had
        return _(DELTA_MAP_CAPTION_WITH_MINIMUM if with_minimum else DELTA_MAP_CAPTION)
    opening = _(MAP_CAPTION_WITH_MINIMUM if with_minimum else MAP_CAPTION) % {"limit": layout.limit_text}
    rearward = ONE_REAR_REARWARD if layout.n_rear == 1 else TWO_REAR_REARWARD
    return f"{opening} {_(rearward)}"


def figure_text(value: float | Decimal | None, places: int, unit: str = "") -> str:
    """A figure to `places` decimals with its unit, or 'Not known'."""
    if value is None:
        return not_known()
    text = fixed(value, places)
    return f"{text}{unit}" if unit == "°" else f"{text} {unit}".strip()


def critical_speed_text(critical_kmh: float | None, margin: float | None) -> str:
    """'113.8 km/h', 'None (understeers)': stable at every speed, or 'Not known'."""
    if margin is None:
        return not_known()
    if critical_kmh is None:
        return _(UNDERSTEERS)
    return figure_text(critical_kmh, 1, "km/h")


def readings_text(values: Sequence[str], mean_kg: float, places: int = 1) -> str:
    """The raised front wheel's reading(s): '94.8 kg', or '94.8 kg (mean of 94.8, 94.7, 94.9)'."""
    shown = figure_text(mean_kg, places, "kg")
    return shown if len(values) < 2 else _(MEAN_OF) % {"reading": shown, "readings": ", ".join(values)}


def _english_patterns() -> list[tuple[re.Pattern[str], str]]:
    """The English messages with placeholders as patterns that read a frozen English text back."""
    patterns = []
    for message in (MISSING, MEAN_OF, PASSENGER_SEAT, REVISION):
        pattern = re.escape(message)
        pattern = re.sub(r"%\\\(([a-z]+)\\\)s", r"(?P<\1>.+?)", pattern)
        patterns.append((re.compile(pattern + "$"), message))
    return patterns


def frozen(text: str) -> str:
    """A paper's frozen English text (a label, a value, the missing sentence) in the current language.

    A certificate freezes its estimates in English at issue; a bilingual paper translates them back
    from the English message they were made of. Anything else (a figure, a unit) prints as it is.
    """
    for pattern, message in _english_patterns():
        match = pattern.match(text)
        if match:
            parts = {name: frozen_parts(name, value) for name, value in match.groupdict().items()}
            return _(message) % parts
    return _(text) if text else text


def frozen_parts(name: str, value: str) -> str:
    """One placeholder's frozen English value in the current language (the missing inputs one by one)."""
    if name == "inputs":
        return "; ".join(frozen(part) for part in value.split("; "))
    return value
