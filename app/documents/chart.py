"""The LSF chart of the certificate, drawn with the PDF library's own vector primitives.

x: the loading cases; y: LSF; a dashed line at the 2/3 limit, the region above it shaded
"unstable"; each case a circle (C) or a cross (NC) with its letters beside it, so nothing is
told by colour alone. The chart's text is set in the certificate's embedded font.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction
from typing import Protocol

from fpdf import FPDF

from app.documents import fonts
from app.i18n.active import gettext as _
from app.stability import LSF_LIMIT
from app.web.chart import short_label
from app.wording import verdict_mark


class ChartCase(Protocol):
    """What the chart reads of one loading case (the certificate's CaseFacts, say)."""

    @property
    def occupants(self) -> int: ...
    @property
    def lsf(self) -> Decimal: ...
    @property
    def compliant(self) -> bool: ...


LIMIT = float(LSF_LIMIT)
STEP = 0.05
STEPS = (0.05, 0.1, 0.2, 0.25, 0.5)
MIN_TICK_GAP = 4.5  # mm between two tick labels: more than the height of a 7 pt label
PREFERRED_H, MIN_H = 62.0, 28.0
ABOVE = 6.0  # the legend line above the plotting area
BELOW = 11.0  # the case names and the axis title below it
LEFT, RIGHT = 12.0, 16.0  # tick labels on the left, "limit 2/3" on the right


@dataclass(frozen=True)
class Box:
    """The plotting area on the page (mm)."""

    x: float
    y: float
    w: float
    h: float


def axis_range(values: Sequence[float], limit: Fraction = LSF_LIMIT) -> tuple[float, float]:
    """The y axis: 0.5 to 0.8 around the delta's 2/3 (0.15 to 0.5 around a tadpole's 1/3), widened
    in steps of 0.05 to hold every value with a margin."""
    low = min([float(limit - Fraction(1, 6)), *[v - 0.02 for v in values]])
    high = max([float(limit + Fraction(2, 15)), *[v + 0.02 for v in values]])
    return math.floor(low / STEP + 1e-9) * STEP, math.ceil(high / STEP - 1e-9) * STEP


def tick_step(low: float, high: float, height: float) -> float:
    """The smallest tick step whose labels stand at least MIN_TICK_GAP apart."""
    for step in STEPS:
        if height * step / (high - low) >= MIN_TICK_GAP:
            return step
    return STEPS[-1]


def chart_height(room: float) -> float | None:
    """The plotting area's height for `room` mm below the heading (None: too little room)."""
    height = min(PREFERRED_H, room - ABOVE - BELOW)
    return height if height >= MIN_H else None


SECOND_LINE = 3.5  # mm: a bilingual chart's translated legend and axis title, each a line more


def _fitted(pdf: FPDF, text: str, width: float, size: float = 7) -> None:
    """Set the chart's regular face at `size` points, or smaller until `text` is `width` mm wide."""
    pdf.set_font(fonts.FAMILY, "", size)
    wide = pdf.get_string_width(text)
    if wide > width:
        pdf.set_font(fonts.FAMILY, "", size * width / wide)


def draw_chart(
    pdf: FPDF,
    box: Box,
    cases: Sequence[ChartCase],
    *,
    limit: Fraction = LSF_LIMIT,
    say: Callable[[Callable[[], str]], list[str]] | None = None,
) -> tuple[float, float, float, float]:
    """Draw the chart of LSF per loading case below `box.y`, against the layout's `limit` (2/3 for the
    delta); returns the area it covers (x, y, w, h). `say` words the legend and the axis title in
    the paper's languages (English, then its translation a line lower)."""
    limit_text = f"{limit.numerator}/{limit.denominator}"

    def legend_words() -> str:
        return _("Shaded: unstable (LSF at or above %(limit)s)") % {"limit": limit_text}

    def axis_words() -> str:
        return _("Loading case (occupants)")

    legend = say(legend_words) if say else [legend_words()]
    axis = say(axis_words) if say else [axis_words()]
    above = ABOVE + SECOND_LINE * (len(legend) - 1)
    below = BELOW + SECOND_LINE * (len(axis) - 1)
    box = Box(box.x, box.y + above, box.w, box.h)
    values = [float(case.lsf) for case in cases]
    low, high = axis_range(values, limit)

    def y_of(value: float) -> float:
        return box.y + box.h * (high - value) / (high - low)

    def x_of(index: int) -> float:
        return box.x + box.w * (index + 0.5) / max(len(cases), 1)

    limit_y = y_of(float(limit))
    pdf.set_fill_color(232, 232, 232)
    pdf.rect(box.x, box.y, box.w, limit_y - box.y, style="F")
    pdf.set_font(fonts.FAMILY, "", 7)
    pdf.text(box.x - 9, box.y - 2.5, "LSF")
    pdf.set_text_color(70, 70, 70)
    pdf.text(box.x + 2, box.y - 2.5 - SECOND_LINE * (len(legend) - 1), legend[0])
    for line in legend[1:]:
        _fitted(pdf, line, box.w + RIGHT - 2)
        pdf.text(box.x + 2, box.y - 2.5, line)
    pdf.set_font(fonts.FAMILY, "", 7)

    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.3)
    pdf.line(box.x, box.y, box.x, box.y + box.h)
    pdf.line(box.x, box.y + box.h, box.x + box.w, box.y + box.h)
    pdf.set_text_color(0, 0, 0)
    step = tick_step(low, high, box.h)
    first = math.ceil(low / step - 1e-9)
    for i in range(first, math.floor(high / step + 1e-9) + 1):
        value = i * step
        pdf.line(box.x - 1.2, y_of(value), box.x, y_of(value))
        pdf.text(box.x - 9, y_of(value) + 1, f"{value:.2f}")

    pdf.set_dash_pattern(dash=1.5, gap=1)
    pdf.set_line_width(0.4)
    pdf.line(box.x, limit_y, box.x + box.w, limit_y)
    pdf.set_dash_pattern()
    pdf.set_font(fonts.FAMILY, "B", 7)
    pdf.text(box.x + box.w + 4, limit_y + 1, f"limit {limit_text}")

    pdf.set_line_width(0.2)
    pdf.set_draw_color(120, 120, 120)
    for i in range(1, len(cases)):
        pdf.line(x_of(i - 1), y_of(values[i - 1]), x_of(i), y_of(values[i]))

    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.45)
    for i, case in enumerate(cases):
        cx, cy = x_of(i), y_of(values[i])
        if case.compliant:
            pdf.circle(cx, cy, 1.4, style="D")
        else:
            pdf.line(cx - 1.4, cy - 1.4, cx + 1.4, cy + 1.4)
            pdf.line(cx - 1.4, cy + 1.4, cx + 1.4, cy - 1.4)
        pdf.set_font(fonts.FAMILY, "B", 7)
        mark = verdict_mark(case.compliant)
        # Above its marker (below it near the top), centred: beside it, a label runs into the next case.
        pdf.text(cx - pdf.get_string_width(mark) / 2, cy - 2.4 if cy - box.y > 6 else cy + 4.6, mark)
        pdf.set_font(fonts.FAMILY, "", 7)
        label = short_label(case.occupants)
        pdf.text(cx - pdf.get_string_width(label) / 2, box.y + box.h + 4, label)
    pdf.set_font(fonts.FAMILY, "", 7)
    pdf.text(box.x + box.w / 2 - 14, box.y + box.h + 8.5, axis[0])
    for line in axis[1:]:
        _fitted(pdf, line, box.w + RIGHT - 2)
        pdf.text(
            max(box.x - LEFT + 1, box.x + box.w / 2 - pdf.get_string_width(line) / 2),
            box.y + box.h + 8.5 + SECOND_LINE,
            line,
        )
    pdf.set_line_width(0.2)
    return box.x - LEFT, box.y - above, box.w + LEFT + RIGHT, box.h + above + below
