"""The LSF chart of one inspection as inline SVG, drawn on the server (no script, no CDN).

x: the loading cases; y: LSF; a line at 2/3 labelled "limit 2/3" with the region above it shaded
"unstable"; compliant cases are circles marked C, non-compliant ones crosses marked NC.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from markupsafe import Markup, escape

from app.stability import LSF_LIMIT

WIDTH, HEIGHT = 480, 340
LEFT, RIGHT, TOP, BOTTOM = 62, 86, 20, 60  # the right margin holds the label of the limit line
STEP = 0.05
LIMIT = float(LSF_LIMIT)
LIMIT_TEXT = f"{LIMIT:.3f}"
TITLE = "Lateral Stability Factor per loading case, against the 2/3 limit"


@dataclass(frozen=True)
class ChartPoint:
    """One loading case on the chart."""

    short_label: str  # under the axis: None, Driver, +1, ...
    long_label: str  # in the text alternative: Driver + 1 passenger
    lsf: float
    compliant: bool


def short_label(occupants: int) -> str:
    """The axis label of a loading case: None, Driver, +1, +2, ..."""
    return {0: "None", 1: "Driver"}.get(occupants, f"+{occupants - 1}")


def y_range(values: Sequence[float]) -> tuple[float, float]:
    """The y axis: about 0.5 to 0.8, widened in steps of 0.05 to hold every point."""
    low = min([0.5, *(v - 0.02 for v in values)])
    high = max([0.8, *(v + 0.02 for v in values)])
    return math.floor(round(low / STEP, 6)) * STEP, math.ceil(round(high / STEP, 6)) * STEP


def _text(x: float, y: float, content: str, *, anchor: str = "middle", size: int = 15, cls: str = "") -> str:
    cls_attr = f' class="{cls}"' if cls else ""
    return (
        f'<text x="{x:.1f}" y="{y:.1f}" text-anchor="{anchor}" font-size="{size}"{cls_attr}>'
        f"{escape(content)}</text>"
    )


def marker(x: float, y: float, compliant: bool, *, hollow: bool = False) -> str:
    """A case's marker: a green circle when compliant, a red cross when not (hollow: grey, smaller)."""
    if compliant:
        fill, stroke = ("#ffffff", "#505a5f") if hollow else ("#00703c", "#ffffff")
        return (
            f'<circle class="chart__c" cx="{x:.1f}" cy="{y:.1f}" r="{6 if hollow else 7}" '
            f'fill="{fill}" stroke="{stroke}" stroke-width="2"/>'
        )
    d = 6 if hollow else 7
    return (
        f'<path class="chart__nc" d="M{x - d:.1f} {y - d:.1f} L{x + d:.1f} {y + d:.1f} '
        f'M{x - d:.1f} {y + d:.1f} L{x + d:.1f} {y - d:.1f}" stroke="{"#505a5f" if hollow else "#b10e1e"}" '
        f'stroke-width="{2.5 if hollow else 4}" stroke-linecap="round" fill="none"/>'
    )


def case_list(points: Sequence[ChartPoint]) -> str:
    """Every case's LSF and verdict in words: 'Driver: 0.658, C (compliant); ...'."""
    return "; ".join(
        f"{p.long_label}: {p.lsf:.3f}, {'C (compliant)' if p.compliant else 'NC (not compliant)'}"
        for p in points
    )


INTRODUCTION = (
    f"Lateral Stability Factor for each loading case against the limit of 2/3 ({LIMIT_TEXT}); "
    "a case above the line is unstable."
)


def describe(points: Sequence[ChartPoint]) -> str:
    """The chart's text alternative: every case's LSF and verdict, and the limit."""
    return f"{INTRODUCTION} {case_list(points)}."


@dataclass(frozen=True)
class Plot:
    """A chart's scales: LSF from `low` to `high` upwards, and `slots` loading cases across."""

    low: float
    high: float
    slots: int
    step: float = STEP  # between grid lines

    @property
    def width(self) -> float:
        """The plot area's width."""
        return WIDTH - LEFT - RIGHT

    @property
    def height(self) -> float:
        """The plot area's height."""
        return HEIGHT - TOP - BOTTOM

    def y_of(self, value: float) -> float:
        """The y coordinate of an LSF."""
        return TOP + (self.high - value) / (self.high - self.low) * self.height

    def x_of(self, index: float) -> float:
        """The x coordinate of a loading case's slot centre (fractions move within the slots)."""
        return LEFT + (index + 0.5) * self.width / max(self.slots, 1)


def plot_for(values: Sequence[float], slots: int) -> Plot:
    """The scales that hold every value, in `slots` loading cases."""
    low, high = y_range(values)
    return Plot(low, high, slots)


def chart_frame(plot: Plot, *, chart_id: str, title: str, description: str) -> list[str]:
    """The opening of the SVG: title and text alternative, the unstable region, grid, 2/3 line, border."""
    limit_y = plot.y_of(LIMIT)
    plot_w, plot_h = plot.width, plot.height
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" class="chart" viewBox="0 0 {WIDTH} {HEIGHT}" '
        f'role="img" aria-labelledby="{chart_id}-title {chart_id}-desc" id="{chart_id}" focusable="false">',
        f'<title id="{chart_id}-title">{escape(title)}</title>',
        f'<desc id="{chart_id}-desc">{escape(description)}</desc>',
        f'<rect class="chart__unstable" x="{LEFT}" y="{TOP}" width="{plot_w}" height="{limit_y - TOP:.1f}" '
        'fill="#fbe3df"/>',
        _text(LEFT + 8, TOP + 21, "unstable", anchor="start", size=17, cls="chart__region"),
        _text(LEFT + 8, TOP + plot_h - 10, "stable", anchor="start", size=17, cls="chart__region"),
    ]
    ticks = round((plot.high - plot.low) / plot.step)
    for i in range(ticks + 1):
        value = plot.low + i * plot.step
        y = plot.y_of(value)
        parts.append(f'<line x1="{LEFT}" x2="{LEFT + plot_w}" y1="{y:.1f}" y2="{y:.1f}" stroke="#d0d3d4"/>')
        parts.append(_text(LEFT - 8, y + 5, f"{value:.2f}", anchor="end", size=16))
    parts.append(
        f'<line class="chart__limit" x1="{LEFT}" x2="{LEFT + plot_w}" y1="{limit_y:.1f}" y2="{limit_y:.1f}" '
        'stroke="#0b0c0c" stroke-width="2.5" stroke-dasharray="8 5"/>'
    )
    parts.append(
        _text(LEFT + plot_w + 6, limit_y + 5, "limit 2/3", anchor="start", size=16, cls="chart__limit-label")
    )
    parts.append(
        f'<rect x="{LEFT}" y="{TOP}" width="{plot_w}" height="{plot_h}" fill="none" stroke="#505a5f"/>'
    )
    return parts


def case_axis_label(plot: Plot, index: int, label: str) -> str:
    """A loading case's label under the x axis."""
    return _text(plot.x_of(index), TOP + plot.height + 24, label, size=17)


def chart_close(plot: Plot) -> list[str]:
    """The axis titles and the end of the SVG."""
    middle = TOP + plot.height / 2
    return [
        _text(LEFT + plot.width / 2, HEIGHT - 8, "Loading case (occupants)", size=17),
        f'<text x="16" y="{middle:.1f}" text-anchor="middle" font-size="17" '
        f'transform="rotate(-90 16 {middle:.1f})">LSF</text>',
        "</svg>",
    ]


def polyline(
    plot: Plot,
    values: Sequence[float],
    *,
    stroke: str,
    width: float,
    dash: str = "",
    cls: str = "",
    shift: float = 0.0,
) -> str:
    """A line through one value per loading case (`shift`: a fraction of a slot sideways)."""
    points = " ".join(f"{plot.x_of(i + shift):.1f},{plot.y_of(v):.1f}" for i, v in enumerate(values))
    dash_attr = f' stroke-dasharray="{dash}"' if dash else ""
    cls_attr = f' class="{cls}"' if cls else ""
    return (
        f'<polyline{cls_attr} points="{points}" fill="none" stroke="{stroke}" '
        f'stroke-width="{width}"{dash_attr}/>'
    )


def series(
    plot: Plot, points: Sequence[ChartPoint], *, shift: float = 0.0, muted: bool = False, name: str = ""
) -> list[str]:
    """One line of cases: a polyline and each marker, marked C or NC (muted: hollow, dashed, unmarked)."""
    parts = []
    if len(points) > 1:
        values = [p.lsf for p in points]
        parts.append(
            polyline(plot, values, stroke="#505a5f", width=1.5, dash="6 4" if muted else "", shift=shift)
        )
    data = f' data-series="{name}"' if name else ""
    for i, point in enumerate(points):
        x, y = plot.x_of(i + shift), plot.y_of(point.lsf)
        parts.append(f'<g class="chart__point" data-verdict="{"C" if point.compliant else "NC"}"{data}>')
        parts.append(marker(x, y, point.compliant, hollow=muted))
        if not muted:
            # C points lie below the line and NC points above it: label each away from the line.
            label_y = y + 27 if point.compliant else y - 14
            parts.append(_text(x, label_y, "C" if point.compliant else "NC", size=17, cls="chart__verdict"))
        parts.append("</g>")
    return parts


def _markup(parts: Sequence[str]) -> Markup:
    # Every piece of text went through escape(); the rest is markup built here from numbers.
    return Markup("".join(parts))  # noqa: S704


def lsf_chart(points: Sequence[ChartPoint], *, chart_id: str = "lsf-chart") -> Markup:
    """The whole SVG element, safe to place in a page."""
    plot = plot_for([p.lsf for p in points], len(points))
    parts = chart_frame(plot, chart_id=chart_id, title=TITLE, description=describe(points))
    parts += series(plot, points)
    parts += [case_axis_label(plot, i, point.short_label) for i, point in enumerate(points)]
    return _markup([*parts, *chart_close(plot)])


def before_after_chart(
    before: Sequence[ChartPoint], after: Sequence[ChartPoint], *, remedy: str, chart_id: str = "remedy-chart"
) -> Markup:
    """Each case's LSF today (hollow, dashed) and after `remedy` (marked C or NC), on one scale."""
    plot = plot_for([p.lsf for p in [*before, *after]], len(before))
    title = f"LSF per loading case today and {remedy}, against the 2/3 limit"
    after_words = f"{remedy[:1].upper()}{remedy[1:]}: {case_list(after)}"
    description = f"{INTRODUCTION} Today: {case_list(before)}. {after_words}."
    parts = chart_frame(plot, chart_id=chart_id, title=title, description=description)
    parts += series(plot, before, shift=-0.08, muted=True, name="before")
    parts += series(plot, after, shift=0.08, name="after")
    parts += [case_axis_label(plot, i, point.short_label) for i, point in enumerate(before)]
    return _markup([*parts, *chart_close(plot)])
