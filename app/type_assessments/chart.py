"""The type assessment's chart: each vehicle's LSF per case as points, the mean and the 95 % bound as lines.

Drawn with app/web/chart.py's scales, frame and markers, so it reads like every other LSF chart.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from markupsafe import Markup

from app.stability import LSF_LIMIT
from app.web.chart import (
    Plot,
    case_axis_label,
    chart_close,
    chart_frame,
    marker,
    plot_for,
    polyline,
    short_label,
)
from app.wording import occupancy

TITLE = "Each vehicle's LSF per loading case, the type's mean and 95 % upper bound, against the 2/3 limit"
MEAN_COLOUR, BOUND_COLOUR = "#1d70b8", "#912b88"
FINE_STEP = 0.01
FINE_SPAN = 0.12  # a sample this close together gets grid lines 0.01 apart, so its spread shows


def zoomed_plot(values: Sequence[float], slots: int, limit: Fraction = LSF_LIMIT) -> Plot:
    """The scales: to 0.01 around the values and the limit when they lie close, else the usual 0.05."""
    span = [*values, float(limit)]
    low = math.floor(round((min(span) - 0.004) / FINE_STEP, 6)) * FINE_STEP
    high = math.ceil(round((max(span) + 0.004) / FINE_STEP, 6)) * FINE_STEP
    if high - low > FINE_SPAN:
        return plot_for(values, slots, limit)
    return Plot(low, high, slots, FINE_STEP)


@dataclass(frozen=True)
class SpreadPoint:
    """One loading case of the type: the vehicles' LSF (with their verdicts), the mean and the bound."""

    occupants: int
    vehicles: tuple[tuple[float, bool], ...]
    mean: float
    upper: float
    confident: bool


def describe(cases: Sequence[SpreadPoint], limit: Fraction = LSF_LIMIT) -> str:
    """The chart's text alternative: per case the vehicles' range, the mean, the bound and the verdict."""
    parts = "; ".join(
        f"{occupancy(c.occupants)}: vehicles {min(v for v, _ in c.vehicles):.3f} to "
        f"{max(v for v, _ in c.vehicles):.3f}, mean {c.mean:.3f}, 95 % upper bound {c.upper:.3f}, "
        f"{'C (compliant with confidence)' if c.confident else 'NC (not shown compliant)'}"
        for c in cases
    )
    return (
        "Lateral Stability Factor of each vehicle per loading case, with the type's mean and one-sided "
        f"95 % upper bound, against the limit of {limit.numerator}/{limit.denominator}; a case complies "
        "only when its bound is below it. "
        f"{parts}."
    )


def spread_chart(
    cases: Sequence[SpreadPoint], *, chart_id: str = "type-chart", limit: Fraction = LSF_LIMIT
) -> Markup:
    """The whole SVG element, safe to place in a page, against the layout's limit (2/3 on a delta)."""
    values = [v for c in cases for v, _ in c.vehicles] + [c.upper for c in cases]
    plot = zoomed_plot(values, len(cases), limit)
    title = TITLE.replace("2/3", f"{limit.numerator}/{limit.denominator}")
    parts = chart_frame(plot, chart_id=chart_id, title=title, description=describe(cases, limit), limit=limit)
    for i, case in enumerate(cases):
        count = len(case.vehicles)
        parts.append(f'<g class="chart__vehicles" data-occupants="{case.occupants}">')
        for j, (lsf, compliant) in enumerate(case.vehicles):
            # The vehicles side by side within the case's slot, so equal values stay visible.
            offset = (j - (count - 1) / 2) * min(0.18, 0.6 / max(count, 1))
            parts.append(marker(plot.x_of(i + offset), plot.y_of(lsf), compliant))
        parts.append("</g>")
        parts.append(case_axis_label(plot, i, short_label(case.occupants)))
    parts.append(polyline(plot, [c.mean for c in cases], stroke=MEAN_COLOUR, width=3, cls="chart__mean"))
    parts.append(
        polyline(plot, [c.upper for c in cases], stroke=BOUND_COLOUR, width=3, dash="3 4", cls="chart__upper")
    )
    parts += chart_close(plot)
    # The text went through escape() in app/web/chart.py; the rest is markup built from numbers.
    return Markup("".join(parts))  # noqa: S704
