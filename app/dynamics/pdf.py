"""The document's section beyond the static test: the estimates per case, their inputs and the stability map.

The map's geometry comes from app/web/chart.py (`map_geometry`), the same as the page's SVG; here it
is only drawn, with the PDF library's own primitives and the document's embedded font.
"""

from __future__ import annotations

import unicodedata

from app.documents import fonts
from app.documents.chart import Box
from app.documents.layout import CONTENT_W, MARGIN, PAGE_W, SECOND_RGB, Page, line_height, second_size
from app.dynamics.facts import CaseEstimateFacts, EstimateFacts
from app.dynamics.wording import frozen, section_lead, section_title
from app.i18n.active import gettext as _
from app.i18n.active import use_locale
from app.stability import DELTA, Layout, case_label
from app.web.chart import MapGeometry, map_geometry
from app.wording import case_name


def headings() -> tuple[str, ...]:
    """The estimates table's headings."""
    return (
        _("Occupants"),
        _("Centre of gravity height"),
        _("Rollover threshold"),
        _("Tilt angle"),
        _("Critical speed"),
    )


WIDTHS = (46.0, 34.0, 30.0, 24.0, 46.0)
ALIGN = ("L", "R", "R", "R", "R")
SIZE = 8.0
PADDING = 1.2
SECOND_ROW_H = line_height(second_size(SIZE))  # a bilingual row's line in its second language
MAP_W, MAP_H = 92.0, 46.0  # the plotting area (mm)
MAP_LEFT, MAP_ABOVE, MAP_BELOW = 9.0, 7.0, 9.0  # tick labels, the axis title and legend, the LSF axis


def _name(label: str) -> str:
    """A stored case label as the document names it (the empty case is never plain 'None')."""
    return case_name(0) if label == case_label(0) else label


def draw_estimates(pdf: Page, estimates: EstimateFacts, layout: Layout = DELTA) -> None:
    """The whole section on one page (a new one if it does not fit below the chart); the map's limit
    line is the vehicle's `layout`'s."""
    row_h = line_height(SIZE) + 0.8
    says = [lambda i=i: headings()[i] for i in range(len(WIDTHS))]
    heading_h = max(
        pdf.measure_words(w - 2 * PADDING, say, SIZE, bold=True) for w, say in zip(WIDTHS, says, strict=True)
    )

    # The estimates were frozen in English at issue: each language's words are read back from them.
    def lead() -> str:
        return f"{section_lead()} {frozen(estimates.missing)}" if estimates.missing else section_lead()

    points = estimates.map_points
    map_h = MAP_ABOVE + MAP_H + MAP_BELOW if points else 0.0

    def inputs() -> str:
        listed = "; ".join(f"{frozen(label)}: {frozen(value)}" for label, value in estimates.inputs)
        return _("Inputs used: %(inputs)s.") % {"inputs": listed}

    inputs_w = CONTENT_W - (MAP_LEFT + MAP_W + 6 if points else 0)
    height = (
        pdf.measure_words(CONTENT_W, section_title, 11, bold=True)
        + pdf.measure_words(CONTENT_W, lead, 8)
        + heading_h
        + 1.2
        + row_h * len(estimates.cases)
        + SECOND_ROW_H * sum(_second_cells(pdf, case) is not None for case in estimates.cases)
        + 3
        + max(map_h, pdf.measure_words(inputs_w, inputs, 7.5))
    )
    pdf.room(height + 3)
    y = pdf.words(MARGIN, pdf.get_y() + 3, CONTENT_W, section_title, 11, bold=True)
    y = pdf.words(MARGIN, y, CONTENT_W, lead, 8)
    y = _table(pdf, estimates, y, heading_h, row_h) + 3
    if points:
        geometry = map_geometry(points, estimates.min_rollover_g, layout.limit)
        box = Box(MARGIN + MAP_LEFT, y + MAP_ABOVE, MAP_W, MAP_H)
        area = draw_map(pdf, box, geometry, limit_text=layout.limit_text)
        pdf.region("map", *area)
        beside = area[0] + area[2] + 4
        pdf.words(beside, y, PAGE_W - MARGIN - beside, inputs, 7.5)
        pdf.set_xy(MARGIN, area[1] + area[3] + 3)
    else:
        pdf.set_xy(MARGIN, pdf.words(MARGIN, y, CONTENT_W, inputs, 7.5) + 3)


def _cells(case: CaseEstimateFacts) -> tuple[str, ...]:
    """One case's row as printed in English (the frozen words)."""
    return (_name(case.label), case.cg_height, case.rollover_threshold, case.tilt_angle, case.critical_speed)


def _second_cells(pdf: Page, case: CaseEstimateFacts) -> tuple[str, ...] | None:
    """A bilingual paper's row again in its second language, where a word differs (e.g. 'Not known')."""
    if pdf.second_language is None:
        return None
    english = _cells(case)
    with use_locale(pdf.second_language):
        # The case's name stays as in English here: the loading cases table above names it in both.
        said = (english[0], *(unicodedata.normalize("NFC", frozen(cell)) for cell in english[1:]))
    return None if said == english else said


def _table(pdf: Page, estimates: EstimateFacts, top: float, heading_h: float, row_h: float) -> float:
    x = MARGIN
    pdf.set_fill_color(225, 225, 225)
    pdf.set_draw_color(0, 0, 0)
    for i, (width, align) in enumerate(zip(WIDTHS, ALIGN, strict=True)):
        pdf.rect(x, top, width, heading_h + 1.2, style="DF")
        say = lambda i=i: headings()[i]  # noqa: E731
        pdf.words(x + PADDING, top + 0.6, width - 2 * PADDING, say, SIZE, bold=True, align=align)
        x += width
    y = top + heading_h + 1.2
    pdf.style(SIZE)
    pdf.c_margin = PADDING
    for case in estimates.cases:
        english, second = _cells(case), _second_cells(pdf, case)
        if second is None:
            pdf.set_xy(MARGIN, y)
            for width, align, value in zip(WIDTHS, ALIGN, english, strict=True):
                pdf.cell(
                    width, row_h, pdf.printable(value), border=1, align=align, new_x="RIGHT", new_y="TOP"
                )
            y += row_h
            continue
        height = row_h + SECOND_ROW_H
        x = MARGIN
        for i, (width, align) in enumerate(zip(WIDTHS, ALIGN, strict=True)):
            pdf.rect(x, y, width, height, style="D")
            pdf.set_xy(x, y)
            pdf.cell(width, row_h, pdf.printable(english[i]), align=align)
            if second[i] != english[i]:
                colour = pdf.text_color
                pdf.set_text_color(*SECOND_RGB)
                pdf.box(x, y + row_h - 0.4, width, second[i], second_size(SIZE), align=align)
                pdf.text_color = colour
                pdf.style(SIZE)
            x += width
        y += height
    pdf.c_margin = 0
    return y


def draw_map(
    pdf: Page, box: Box, geometry: MapGeometry, *, limit_text: str = DELTA.limit_text
) -> tuple[float, float, float, float]:
    """Draw the stability map's plotting area at `box`, its limit line labelled with `limit_text` ("2/3"
    on a delta); returns the area it covers with its labels."""

    def x_of(across: float) -> float:
        return box.x + across * box.w

    def y_of(up: float) -> float:
        return box.y + box.h - up * box.h

    limit_x = x_of(geometry.limit_x)
    pdf.set_fill_color(232, 232, 232)
    pdf.rect(limit_x, box.y, box.x + box.w - limit_x, box.h, style="F")
    pdf.set_font(fonts.FAMILY, "", 7)
    pdf.text(box.x - MAP_LEFT + 1, box.y - MAP_ABOVE + 2.5, "Rollover threshold (g)")
    pdf.set_text_color(70, 70, 70)
    pdf.text(box.x + 30, box.y - MAP_ABOVE + 2.5, "Circle: C. Cross: NC. Shaded: yaw-unstable.")
    pdf.set_text_color(0, 0, 0)
    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.3)
    pdf.line(box.x, box.y, box.x, box.y + box.h)
    pdf.line(box.x, box.y + box.h, box.x + box.w, box.y + box.h)
    for up, label in geometry.y_ticks:
        pdf.line(box.x - 1.2, y_of(up), box.x, y_of(up))
        pdf.text(box.x - 6, y_of(up) + 1, label)
    for across, label in geometry.x_ticks:
        pdf.line(x_of(across), box.y + box.h, x_of(across), box.y + box.h + 1.2)
        pdf.text(x_of(across) - pdf.get_string_width(label) / 2, box.y + box.h + 4, label)
    pdf.text(box.x + box.w / 2 - 4, box.y + box.h + 8, "LSF")

    pdf.set_dash_pattern(dash=1.5, gap=1)
    pdf.set_line_width(0.4)
    pdf.line(limit_x, box.y, limit_x, box.y + box.h)
    pdf.set_font(fonts.FAMILY, "B", 7)
    pdf.text(limit_x + 1, box.y + 3, f"limit {limit_text}")
    if geometry.min_rollover is not None:
        up, label = geometry.min_rollover
        pdf.set_dash_pattern(dash=0.4, gap=0.8)
        pdf.line(box.x, y_of(up), box.x + box.w, y_of(up))
        pdf.text(box.x + 1, y_of(up) - 1, label)
    pdf.set_dash_pattern()

    pdf.set_line_width(0.45)
    for across, up, point in geometry.points:
        cx, cy = x_of(across), y_of(up)
        if point.compliant:
            pdf.circle(cx, cy, 1.4, style="D")
        else:
            pdf.line(cx - 1.4, cy - 1.4, cx + 1.4, cy + 1.4)
            pdf.line(cx - 1.4, cy + 1.4, cx + 1.4, cy - 1.4)
        pdf.set_font(fonts.FAMILY, "", 7)
        label = point.short_label
        # Below its marker (above it near the axis): the limit and minimum lines run above most points.
        below = box.y + box.h - cy > 6
        pdf.text(cx - pdf.get_string_width(label) / 2, cy + 4.6 if below else cy - 2.4, label)
    pdf.set_line_width(0.2)
    return box.x - MAP_LEFT, box.y - MAP_ABOVE, box.w + MAP_LEFT + 2, box.h + MAP_ABOVE + MAP_BELOW
