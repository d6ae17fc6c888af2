"""The LSF chart of one inspection as inline SVG, drawn on the server (no script, no CDN).

x: the loading cases; y: LSF; a line at the layout's limit labelled "limit 2/3" on a delta ("limit 1/3"
on a tadpole) with the region above it shaded "unstable"; compliant cases are circles marked C,
non-compliant ones crosses marked NC.

The stability map (estimates) puts each case at (LSF, rollover threshold) with the same markers:
the layout's limit line (2/3 on a delta) up the map, a regulator's minimum rollover threshold as a
line across when one is set.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from markupsafe import Markup, escape

from app.i18n.active import gettext as _
from app.stability import LSF_LIMIT
from app.wording import verdict_mark

WIDTH, HEIGHT = 480, 340
LEFT, RIGHT, TOP, BOTTOM = 62, 86, 20, 60  # the right margin holds the label of the limit line
STEP = 0.05
# Every label is at least this many units: 11.7 px where the 480-unit chart is 330 px wide (a 360 px phone).
LABEL_SIZE = 17


@dataclass(frozen=True)
class ChartPoint:
    """One loading case on the chart."""

    short_label: str  # under the axis: None, Driver, +1, ...
    long_label: str  # in the text alternative: Driver + 1 passenger
    lsf: float
    compliant: bool


def short_label(occupants: int) -> str:
    """The axis label of a loading case: Empty, Driver, +1, +2, ..."""
    return {0: _("Empty"), 1: _("Driver")}.get(occupants, f"+{occupants - 1}")


def y_range(values: Sequence[float], limit: Fraction = LSF_LIMIT) -> tuple[float, float]:
    """The y axis: about 0.5 to 0.8 around the delta's 2/3 (0.15 to 0.5 around a tadpole's 1/3),
    widened in steps of 0.05 to hold every point."""
    low = min([float(limit - Fraction(1, 6)), *(v - 0.02 for v in values)])
    high = max([float(limit + Fraction(2, 15)), *(v + 0.02 for v in values)])
    return math.floor(round(low / STEP, 6)) * STEP, math.ceil(round(high / STEP, 6)) * STEP


def _text(
    x: float, y: float, content: str, *, anchor: str = "middle", size: int = LABEL_SIZE, cls: str = ""
) -> str:
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


def _verdict_words(compliant: bool) -> str:
    return _("C (compliant)") if compliant else _("NC (not compliant)")


def case_list(points: Sequence[ChartPoint]) -> str:
    """Every case's LSF and verdict in words: 'Driver: 0.658, C (compliant); ...'."""
    return "; ".join(f"{p.long_label}: {p.lsf:.3f}, {_verdict_words(p.compliant)}" for p in points)


def introduction(limit: Fraction = LSF_LIMIT) -> str:
    """The opening of a chart's text alternative: what it shows, against which limit."""
    return _(
        "Lateral Stability Factor for each loading case against the limit of %(limit)s (%(decimal)s); "
        "a case above the line is unstable."
    ) % {"limit": f"{limit.numerator}/{limit.denominator}", "decimal": f"{float(limit):.3f}"}


INTRODUCTION = introduction()


def title_for(limit: Fraction = LSF_LIMIT) -> str:
    """The chart's title, naming the limit of the vehicle's layout."""
    return _("Lateral Stability Factor per loading case, against the %(limit)s limit") % {
        "limit": f"{limit.numerator}/{limit.denominator}"
    }


def describe(points: Sequence[ChartPoint], limit: Fraction = LSF_LIMIT) -> str:
    """The chart's text alternative: every case's LSF and verdict, and the limit."""
    return f"{introduction(limit)} {case_list(points)}."


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


def plot_for(values: Sequence[float], slots: int, limit: Fraction = LSF_LIMIT) -> Plot:
    """The scales that hold every value and the limit, in `slots` loading cases."""
    low, high = y_range(values, limit)
    return Plot(low, high, slots)


def _opening(chart_id: str, title: str, description: str) -> str:
    """The svg element's start, its title and its text alternative (every chart)."""
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" class="chart" viewBox="0 0 {WIDTH} {HEIGHT}" '
        f'role="img" aria-labelledby="{chart_id}-title {chart_id}-desc" id="{chart_id}" focusable="false">'
        f'<title id="{chart_id}-title">{escape(title)}</title>'
        f'<desc id="{chart_id}-desc">{escape(description)}</desc>'
    )


def _frame(x: float, y: float, w: float, h: float) -> str:
    return f'<rect x="{x}" y="{y}" width="{w}" height="{h}" fill="none" stroke="#505a5f"/>'


def chart_frame(
    plot: Plot, *, chart_id: str, title: str, description: str, limit: Fraction = LSF_LIMIT
) -> list[str]:
    """The opening of the SVG: title and text alternative, the unstable region, grid, limit line, border."""
    limit_y = plot.y_of(float(limit))
    plot_w, plot_h = plot.width, plot.height
    parts = [
        _opening(chart_id, title, description),
        f'<rect class="chart__unstable" x="{LEFT}" y="{TOP}" width="{plot_w}" height="{limit_y - TOP:.1f}" '
        'fill="#fbe3df"/>',
        _text(LEFT + 8, TOP + 21, _("unstable"), anchor="start", cls="chart__region"),
        _text(LEFT + 8, TOP + plot_h - 10, _("stable"), anchor="start", cls="chart__region"),
    ]
    ticks = round((plot.high - plot.low) / plot.step)
    for i in range(ticks + 1):
        value = plot.low + i * plot.step
        y = plot.y_of(value)
        parts.append(f'<line x1="{LEFT}" x2="{LEFT + plot_w}" y1="{y:.1f}" y2="{y:.1f}" stroke="#d0d3d4"/>')
        parts.append(_text(LEFT - 8, y + 6, f"{value:.2f}", anchor="end"))
    parts.append(
        f'<line class="chart__limit" x1="{LEFT}" x2="{LEFT + plot_w}" y1="{limit_y:.1f}" y2="{limit_y:.1f}" '
        'stroke="#0b0c0c" stroke-width="2.5" stroke-dasharray="8 5"/>'
    )
    label = _("limit %(limit)s") % {"limit": f"{limit.numerator}/{limit.denominator}"}
    parts.append(_text(LEFT + plot_w + 6, limit_y + 6, label, anchor="start", cls="chart__limit-label"))
    parts.append(_frame(LEFT, TOP, plot_w, plot_h))
    return parts


def case_axis_label(plot: Plot, index: int, label: str) -> str:
    """A loading case's label under the x axis."""
    return _text(plot.x_of(index), TOP + plot.height + 24, label)


def chart_close(plot: Plot) -> list[str]:
    """The axis titles and the end of the SVG."""
    middle = TOP + plot.height / 2
    return [
        _text(LEFT + plot.width / 2, HEIGHT - 8, _("Loading case (occupants)")),
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
        parts.append(f'<g class="chart__point" data-verdict="{verdict_mark(point.compliant)}"{data}>')
        parts.append(marker(x, y, point.compliant, hollow=muted))
        if not muted:
            # C points lie below the line and NC points above it: label each away from the line.
            label_y = y + 27 if point.compliant else y - 14
            parts.append(_text(x, label_y, verdict_mark(point.compliant), cls="chart__verdict"))
        parts.append("</g>")
    return parts


def _markup(parts: Sequence[str]) -> Markup:
    # Every piece of text went through escape(); the rest is markup built here from numbers.
    return Markup("".join(parts))  # noqa: S704


def lsf_chart(
    points: Sequence[ChartPoint], *, chart_id: str = "lsf-chart", limit: Fraction = LSF_LIMIT
) -> Markup:
    """The whole SVG element, safe to place in a page, with the limit of the vehicle's layout."""
    plot = plot_for([p.lsf for p in points], len(points), limit)
    title, description = title_for(limit), describe(points, limit)
    parts = chart_frame(plot, chart_id=chart_id, title=title, description=description, limit=limit)
    parts += series(plot, points)
    parts += [case_axis_label(plot, i, point.short_label) for i, point in enumerate(points)]
    return _markup([*parts, *chart_close(plot)])


def before_after_chart(
    before: Sequence[ChartPoint],
    after: Sequence[ChartPoint],
    *,
    remedy: str,
    chart_id: str = "remedy-chart",
    limit: Fraction = LSF_LIMIT,
) -> Markup:
    """Each case's LSF today (hollow, dashed) and after `remedy` (marked C or NC), on one scale."""
    plot = plot_for([p.lsf for p in [*before, *after]], len(before), limit)
    title = _("LSF per loading case today and %(remedy)s, against the %(limit)s limit") % {
        "remedy": remedy,
        "limit": f"{limit.numerator}/{limit.denominator}",
    }
    after_words = f"{remedy[:1].upper()}{remedy[1:]}: {case_list(after)}"
    today = _("Today: %(cases)s.") % {"cases": case_list(before)}
    description = f"{introduction(limit)} {today} {after_words}."
    parts = chart_frame(plot, chart_id=chart_id, title=title, description=description, limit=limit)
    parts += series(plot, before, shift=-0.08, muted=True, name="before")
    parts += series(plot, after, shift=0.08, name="after")
    parts += [case_axis_label(plot, i, point.short_label) for i, point in enumerate(before)]
    return _markup([*parts, *chart_close(plot)])


MAP_TITLE = "Stability map: each loading case's LSF against its rollover threshold"
MAP_LEFT, MAP_RIGHT, MAP_TOP, MAP_BOTTOM = 62, 30, 66, 62  # the top margin: the legend, the limit's label
MAP_X_STEP, MAP_Y_STEP = 0.05, 0.1


@dataclass(frozen=True)
class MapPoint:
    """One loading case on the stability map (estimates: its rollover threshold rests on assumed inputs)."""

    short_label: str
    long_label: str
    lsf: float
    rollover_g: float
    compliant: bool


@dataclass(frozen=True)
class MapGeometry:
    """The map computed once from the data, in unit coordinates (0 left/bottom, 1 right/top): the SVG
    and the PDF only draw it."""

    x_ticks: tuple[tuple[float, str], ...]
    y_ticks: tuple[tuple[float, str], ...]
    limit_x: float
    min_rollover: tuple[float, str] | None  # where its line runs and its label
    points: tuple[tuple[float, float, MapPoint], ...]


def map_range(values: Sequence[float], *, low: float, high: float, step: float) -> tuple[float, float]:
    """An axis from `low` to `high`, widened in whole steps to hold every value with a margin."""
    least = min([low, *(v - step / 2 for v in values)])
    most = max([high, *(v + step / 2 for v in values)])
    return math.floor(round(least / step, 6)) * step, math.ceil(round(most / step, 6)) * step


def map_geometry(
    points: Sequence[MapPoint], min_rollover_g: float | None, limit: Fraction = LSF_LIMIT
) -> MapGeometry:
    """Axes of about 0.55-0.8 around the delta's 2/3 (0.2-0.5 around a tadpole's 1/3) and 0.5-0.9 g,
    widened to hold every point and the minimum line."""
    x_low, x_high = map_range(
        [p.lsf for p in points],
        low=float(limit - Fraction(7, 60)),
        high=float(limit + Fraction(2, 15)),
        step=MAP_X_STEP,
    )
    thresholds = [p.rollover_g for p in points] + ([min_rollover_g] if min_rollover_g is not None else [])
    y_low, y_high = map_range(thresholds, low=0.5, high=0.9, step=MAP_Y_STEP)

    def across(value: float) -> float:
        return (value - x_low) / (x_high - x_low)

    def up(value: float) -> float:
        return (value - y_low) / (y_high - y_low)

    x_ticks = tuple(
        (across(x_low + i * MAP_X_STEP), f"{x_low + i * MAP_X_STEP:.2f}")
        for i in range(round((x_high - x_low) / MAP_X_STEP) + 1)
    )
    y_ticks = tuple(
        (up(y_low + i * MAP_Y_STEP), f"{y_low + i * MAP_Y_STEP:.1f}")
        for i in range(round((y_high - y_low) / MAP_Y_STEP) + 1)
    )
    minimum = None if min_rollover_g is None else (up(min_rollover_g), f"minimum {min_rollover_g:.2f} g")
    return MapGeometry(
        x_ticks=x_ticks,
        y_ticks=y_ticks,
        limit_x=across(float(limit)),
        min_rollover=minimum,
        points=tuple((across(p.lsf), up(p.rollover_g), p) for p in points),
    )


def describe_map(
    points: Sequence[MapPoint], min_rollover_g: float | None, limit: Fraction = LSF_LIMIT
) -> str:
    """The map's text alternative: every case's LSF, threshold and verdict, and the lines."""
    cases = "; ".join(
        _("%(case)s: LSF %(lsf)s, rollover threshold %(threshold)s g, %(verdict)s")
        % {
            "case": p.long_label,
            "lsf": f"{p.lsf:.3f}",
            "threshold": f"{p.rollover_g:.3f}",
            "verdict": _verdict_words(p.compliant),
        }
        for p in points
    )
    minimum = (
        " "
        + _("The minimum rollover threshold is %(minimum)s g; a case below that line tips too easily.")
        % {"minimum": f"{min_rollover_g:.2f}"}
        if min_rollover_g is not None
        else ""
    )
    opening = _(
        "Each loading case's LSF (across) against its estimated rollover threshold (up). Right of the "
        "%(fraction)s line (%(limit)s) a case is yaw-unstable."
    ) % {"fraction": f"{limit.numerator}/{limit.denominator}", "limit": f"{float(limit):.3f}"}
    return f"{opening}{minimum} {cases}."


@dataclass(frozen=True)
class Box:
    """A rectangle in the chart's units: left, top, right, bottom."""

    left: float
    top: float
    right: float
    bottom: float

    def overlap(self, other: Box) -> float:
        """The area both share (0 when apart)."""
        width = min(self.right, other.right) - max(self.left, other.left)
        height = min(self.bottom, other.bottom) - max(self.top, other.top)
        return max(width, 0) * max(height, 0)

    def outside(self, area: Box) -> float:
        """How much of this box lies outside `area`."""
        inside = self.overlap(area)
        return (self.right - self.left) * (self.bottom - self.top) - inside


MARKER_REACH = 9  # a marker's half width, its stroke included
# Where a label may go around its marker: (dx, dy of the baseline, anchor), nearest first.
LABEL_SPOTS = (
    (0, 26, "middle"),
    (0, -13, "middle"),
    (13, 6, "start"),
    (-13, 6, "end"),
    (13, 24, "start"),
    (-13, 24, "end"),
    (13, -12, "start"),
    (-13, -12, "end"),
    (0, 44, "middle"),
    (0, -31, "middle"),
)


def text_box(x: float, y: float, content: str, anchor: str, size: float = LABEL_SIZE) -> Box:
    """Where a bold label's glyphs lie, estimated generously (0.62 em a character)."""
    width = 0.62 * size * len(content)
    left = {"start": x, "end": x - width}.get(anchor, x - width / 2)
    return Box(left, y - 0.78 * size, left + width, y + 0.24 * size)


def place_labels(
    centres: Sequence[tuple[float, float]], labels: Sequence[str], *, area: Box, avoid: Sequence[Box]
) -> list[tuple[float, float, str]]:
    """Each marker's label (x, y, anchor): the nearest spot that crosses no line, marker or earlier label
    and stays in `area`; where none is free, the spot that overlaps least."""
    taken = [
        *avoid,
        *(Box(x - MARKER_REACH, y - MARKER_REACH, x + MARKER_REACH, y + MARKER_REACH) for x, y in centres),
    ]
    placed = []
    for (x, y), label in zip(centres, labels, strict=True):

        def clash(spot: tuple[int, int, str], x: float = x, y: float = y, label: str = label) -> float:
            box = text_box(x + spot[0], y + spot[1], label, spot[2])
            return sum(box.overlap(other) for other in taken) + 10 * box.outside(area)

        best = min(LABEL_SPOTS, key=clash)  # min keeps the first of equals: the nearest free spot
        dx, dy, anchor = best
        placed.append((x + dx, y + dy, anchor))
        taken.append(text_box(x + dx, y + dy, label, anchor))
    return placed


def stability_map(
    points: Sequence[MapPoint],
    *,
    min_rollover_g: float | None = None,
    chart_id: str = "stability-map",
    limit: Fraction = LSF_LIMIT,
    rear_axle_words: str = "rear wheels",
) -> Markup:
    """The stability map as an SVG element: the layout's limit line (2/3 on a delta), a minimum rollover
    line when one is set; `rear_axle_words` names the LSF's wheels ("rear wheel" on a tadpole)."""
    geometry = map_geometry(points, min_rollover_g, limit)
    plot_w, plot_h = WIDTH - MAP_LEFT - MAP_RIGHT, HEIGHT - MAP_TOP - MAP_BOTTOM
    right, bottom = MAP_LEFT + plot_w, MAP_TOP + plot_h

    def x_of(across: float) -> float:
        return MAP_LEFT + across * plot_w

    def y_of(up: float) -> float:
        return bottom - up * plot_h

    limit_x = x_of(geometry.limit_x)
    parts = [
        _opening(chart_id, MAP_TITLE, describe_map(points, min_rollover_g, limit)),
        f'<rect class="chart__unstable" x="{limit_x:.1f}" y="{MAP_TOP}" '
        f'width="{right - limit_x:.1f}" height="{plot_h}" fill="#fbe3df"/>',
        _text(limit_x + 6, MAP_TOP + 20, "yaw-unstable", anchor="start", cls="chart__region"),
    ]
    if geometry.min_rollover is not None:
        min_y = y_of(geometry.min_rollover[0])
        parts.append(
            f'<rect class="chart__tips" x="{MAP_LEFT}" y="{min_y:.1f}" width="{plot_w}" '
            f'height="{bottom - min_y:.1f}" fill="#fff2cc" fill-opacity="0.7"/>'
        )
    for across, label in geometry.x_ticks:
        x = x_of(across)
        parts.append(f'<line x1="{x:.1f}" x2="{x:.1f}" y1="{MAP_TOP}" y2="{bottom}" stroke="#d0d3d4"/>')
        # Low enough to clear the lowest threshold's label at the corner.
        parts.append(_text(x, bottom + 28, label))
    for up, label in geometry.y_ticks:
        y = y_of(up)
        parts.append(f'<line x1="{MAP_LEFT}" x2="{right}" y1="{y:.1f}" y2="{y:.1f}" stroke="#d0d3d4"/>')
        parts.append(_text(MAP_LEFT - 8, y + 6, label, anchor="end"))
    parts.append(
        f'<line class="chart__limit" x1="{limit_x:.1f}" x2="{limit_x:.1f}" y1="{MAP_TOP}" '
        f'y2="{bottom}" stroke="#0b0c0c" stroke-width="2.5" stroke-dasharray="8 5"/>'
    )
    # The map's own labels are in English, as they always were (the text alternative is translated).
    fraction = f"{limit.numerator}/{limit.denominator}"
    parts.append(_text(limit_x, MAP_TOP - 6, f"limit {fraction}", cls="chart__limit-label"))
    if geometry.min_rollover is not None:
        min_y = y_of(geometry.min_rollover[0])
        parts.append(
            f'<line class="chart__min-rollover" x1="{MAP_LEFT}" x2="{right}" y1="{min_y:.1f}" '
            f'y2="{min_y:.1f}" stroke="#0b0c0c" stroke-width="2.5" stroke-dasharray="2 4"/>'
        )
        parts.append(
            _text(
                MAP_LEFT + 6,
                min_y - 6,
                geometry.min_rollover[1],
                anchor="start",
                cls="chart__limit-label",
            )
        )
    parts.append(_frame(MAP_LEFT, MAP_TOP, plot_w, plot_h))
    centres = [(x_of(across), y_of(up)) for across, up, _point in geometry.points]
    lines = [Box(limit_x - 2, MAP_TOP, limit_x + 2, bottom)]
    if geometry.min_rollover is not None:
        min_y = y_of(geometry.min_rollover[0])
        lines.append(Box(MAP_LEFT, min_y - 2, right, min_y + 2))
    places = place_labels(
        centres,
        [point.short_label for _across, _up, point in geometry.points],
        area=Box(MAP_LEFT, MAP_TOP, right, bottom),
        avoid=lines,
    )
    for (x, y), (_across, _up, point), (label_x, label_y, anchor) in zip(
        centres, geometry.points, places, strict=True
    ):
        parts.append(f'<g class="chart__point" data-verdict="{verdict_mark(point.compliant)}">')
        parts.append(marker(x, y, point.compliant))
        parts.append(_text(label_x, label_y, point.short_label, anchor=anchor, cls="chart__verdict"))
        parts.append("</g>")
    # The legend says what the shapes mean, so neither colour nor shape stands alone.
    parts.append(marker(MAP_LEFT + 8, 14, True))
    parts.append(_text(MAP_LEFT + 22, 20, "C compliant", anchor="start"))
    parts.append(marker(MAP_LEFT + 150, 14, False))
    parts.append(_text(MAP_LEFT + 164, 20, "NC not compliant", anchor="start"))
    parts.append(_text(MAP_LEFT + plot_w / 2, HEIGHT - 6, f"LSF (share of weight on the {rear_axle_words})"))
    parts.append(
        f'<text x="16" y="{MAP_TOP + plot_h / 2:.1f}" text-anchor="middle" font-size="{LABEL_SIZE}" '
        f'transform="rotate(-90 16 {MAP_TOP + plot_h / 2:.1f})">Rollover threshold (g)</text>'
    )
    parts.append("</svg>")
    # As above: every text went through escape(); the rest is markup built here from numbers.
    return Markup("".join(parts))  # noqa: S704
