"""The one-page A4 certificate (or refusal) as a PDF with real, selectable text (fpdf2, core fonts).

Rendered once when the certificate is issued; the bytes are stored and served unchanged. Core
fonts (Helvetica) need no font files, so every machine renders the same; text is kept to Latin-1.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass
from datetime import datetime

import segno
from fpdf import FPDF
from fpdf.enums import RenderStyle

from app.certificates.chart import Box, draw_chart
from app.certificates.facts import CaseFacts, Facts
from app.web.formatting import kg, limit_text, ratio, signed, to_local

MARGIN = 15.0
PAGE_W = 210.0
CONTENT_W = PAGE_W - 2 * MARGIN
PAGE_H = 297.0
VALIDITY_Y = PAGE_H - MARGIN - 14
QR_MASK = 1
COMPACT_AFTER = 6  # more loading cases than this: smaller table rows, reasons in one paragraph
TABLE_HEADINGS = (
    "Occupants",
    "Total weight (kg)",
    "Weight on rear wheels (kg)",
    "Actual LSF",
    "Standard (max)",
    "Variance",
    "Result",
)
_TYPOGRAPHY = str.maketrans({"‘": "'", "’": "'", "“": '"', "”": '"', "–": "-", "—": "-", "…": "..."})


@dataclass(frozen=True)
class CertificateDocument:
    """What the PDF shows: the number, kind, dates, frozen facts and the verify addresses."""

    number: str
    kind: str
    issued_at: datetime
    expires_at: datetime
    facts: Facts
    verify_url: str
    qr_url: str


def latin1(text: str) -> str:
    """Text the core fonts can print: typographic marks simplified, anything else outside Latin-1 as '?'."""
    text = unicodedata.normalize("NFKC", text).translate(_TYPOGRAPHY)
    return text.encode("latin-1", "replace").decode("latin-1")


def when(moment: datetime) -> str:
    """A time in the service's display zone: 23 Nov 2026, 15:05 WAT."""
    local = to_local(moment)
    return f"{local.day} {local:%b %Y, %H:%M} {local.tzname() or 'UTC'}"


def day(moment: datetime) -> str:
    """A date in the service's display zone: 23 November 2026."""
    local = to_local(moment)
    return f"{local.day} {local:%B %Y}"


def title(kind: str) -> str:
    """The document's title for its kind."""
    return "Lateral Stability Certificate" if kind == "compliant" else "Lateral Stability Refusal"


def refusal_reason(case: CaseFacts) -> str:
    """Why one loading case fails, and by how much."""
    excess = -case.variance
    if excess == 0:
        return f"{case.label}: LSF {ratio(case.lsf)} equals the limit {limit_text()}; it must be below it."
    return f"{case.label}: LSF {ratio(case.lsf)} is above the limit {limit_text()} by {ratio(excess)}."


class _Page(FPDF):
    def key_values(self, x: float, width: float, heading: str, rows: list[tuple[str, str]]) -> float:
        """A small heading and label: value lines in a column; returns the y below it."""
        self.set_xy(x, self.get_y())
        self.set_font("helvetica", "B", 11)
        self.cell(width, 6, latin1(heading), new_x="LEFT", new_y="NEXT")
        for label, value in rows:
            self.set_x(x)
            self.set_font("helvetica", "", 9)
            self.cell(34, 5, latin1(label))
            self.set_font("helvetica", "B", 9)
            self.multi_cell(width - 34, 5, latin1(value), new_x="LEFT", new_y="NEXT")
            self.set_x(x)
        return self.get_y()


def render_pdf(document: CertificateDocument) -> bytes:
    """The certificate as PDF bytes; the same document always gives the same bytes."""
    facts = document.facts
    pdf = _Page(orientation="portrait", unit="mm", format="A4")
    pdf.set_creation_date(document.issued_at)
    pdf.set_title(latin1(f"{title(document.kind)} {document.number}"))
    pdf.set_author(latin1(facts.authority))
    pdf.set_subject(latin1(f"{facts.vehicle.registration_number}: {facts.verdict}"))
    pdf.set_creator("trikecert")
    pdf.set_lang("en")
    pdf.set_auto_page_break(auto=False)
    pdf.set_margins(MARGIN, MARGIN, MARGIN)
    pdf.add_page()

    _header(pdf, document)
    top = pdf.get_y() + 3
    pdf.set_y(top)
    vehicle = facts.vehicle
    left = pdf.key_values(
        MARGIN,
        85,
        "Vehicle",
        [
            ("Registration", vehicle.registration_number),
            ("Make", vehicle.make),
            ("Model", vehicle.model),
            ("Year", str(vehicle.model_year) if vehicle.model_year else "not recorded"),
            ("Chassis number", vehicle.chassis_number or "not recorded"),
        ],
    )
    pdf.set_y(top)
    inspection = facts.inspection
    right = pdf.key_values(
        MARGIN + 92,
        CONTENT_W - 92,
        "Inspection",
        [
            ("Station", inspection.station or "not recorded"),
            ("Scale calibration", inspection.scale_calibration or "not recorded"),
            ("Officer", inspection.officer or "none (station submission)"),
            ("Date and time", when(inspection.weighed_at)),
            ("Inspection", f"no. {inspection.id}; occupant {kg(inspection.occupant_mass_kg)} kg"),
        ],
    )
    pdf.set_y(max(left, right) + 3)
    _readings(pdf, facts)
    _verdict(pdf, document)
    _table(pdf, facts)
    _chart_and_qr(pdf, document)
    return bytes(pdf.output())


def _header(pdf: FPDF, document: CertificateDocument) -> None:
    pdf.set_font("helvetica", "B", 11)
    pdf.cell(CONTENT_W, 6, latin1(document.facts.authority), new_x="LMARGIN", new_y="NEXT")
    pdf.set_font("helvetica", "B", 20)
    pdf.cell(CONTENT_W, 10, title(document.kind), new_x="LMARGIN", new_y="NEXT")
    pdf.set_font("helvetica", "", 9)
    pdf.cell(CONTENT_W, 5, "Certificate number", new_x="LMARGIN", new_y="NEXT")
    pdf.set_font("courier", "B", 24)
    pdf.cell(CONTENT_W, 11, document.number, new_x="LMARGIN", new_y="NEXT")
    pdf.set_font("helvetica", "", 9)
    pdf.multi_cell(
        CONTENT_W,
        4.5,
        latin1(
            f"Status when issued: ISSUED. The current status (valid, expired, revoked or superseded) "
            f"is at {document.verify_url}/{document.number}"
        ),
        new_x="LMARGIN",
        new_y="NEXT",
        align="L",
    )
    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.5)
    pdf.line(MARGIN, pdf.get_y() + 1.5, PAGE_W - MARGIN, pdf.get_y() + 1.5)
    pdf.set_line_width(0.2)


def _readings(pdf: FPDF, facts: Facts) -> None:
    pdf.set_font("helvetica", "B", 11)
    pdf.cell(CONTENT_W, 6, "Averaged readings", new_x="LMARGIN", new_y="NEXT")
    pdf.set_font("helvetica", "", 9)
    for reading in facts.readings:
        times = "once" if reading.count == 1 else f"{reading.count} times, spread {kg(reading.spread_kg)} kg"
        pdf.cell(
            CONTENT_W / 2,
            4.6,
            latin1(f"{reading.name}: {kg(reading.mean_kg)} kg (read {times})"),
            new_x="LMARGIN" if reading.wheel in ("left_rear_kg", "overall_kg") else "RIGHT",
            new_y="NEXT" if reading.wheel in ("left_rear_kg", "overall_kg") else "TOP",
        )
    pdf.set_x(MARGIN)
    pdf.ln(2)


def _verdict(pdf: FPDF, document: CertificateDocument) -> None:
    facts = document.facts
    pdf.set_font("helvetica", "B", 12)
    pdf.multi_cell(CONTENT_W, 6, latin1(facts.verdict), new_x="LMARGIN", new_y="NEXT")
    pdf.cell(
        CONTENT_W, 6, latin1(f"Certified maximum occupancy: {facts.occupancy}"), new_x="LMARGIN", new_y="NEXT"
    )
    if document.kind == "refusal":
        pdf.set_font("helvetica", "B", 9)
        pdf.cell(
            CONTENT_W,
            5,
            "Reasons for refusal (cases that fail and by how much):",
            new_x="LMARGIN",
            new_y="NEXT",
        )
        pdf.set_font("helvetica", "", 9)
        failing = facts.failing_cases
        if len(failing) <= COMPACT_AFTER:
            for case in failing:
                pdf.cell(CONTENT_W, 4.5, latin1(f"- {refusal_reason(case)}"), new_x="LMARGIN", new_y="NEXT")
        else:
            text = "; ".join(f"{c.label}: LSF {ratio(c.lsf)}, {ratio(-c.variance)} over" for c in failing)
            pdf.multi_cell(
                CONTENT_W, 4.2, latin1(f"Limit {limit_text()}. {text}."), new_x="LMARGIN", new_y="NEXT"
            )
    pdf.ln(2)


COLUMN_WIDTHS = (34.0, 24.0, 30.0, 20.0, 24.0, 20.0, 18.0)
COLUMN_ALIGN = ("L", "R", "R", "R", "R", "R", "C")
CELL_PADDING = 1.2  # mm left and right of the text in a table cell


def _table(pdf: FPDF, facts: Facts) -> None:
    # Plain bordered cells: fpdf2's table() lays out every cell as a multi-line box, which cost a
    # third of the page's rendering time for rows that are always one line.
    pdf.set_font("helvetica", "B", 11)
    pdf.cell(CONTENT_W, 6, "Loading cases (Table 4 of the study)", new_x="LMARGIN", new_y="NEXT")
    compact = len(facts.cases) > COMPACT_AFTER
    size, line = (7.0, 3.0) if compact else (9.0, 4.6)
    row_h = line + (0.4 if compact else 1.2)
    _table_headings(pdf, size, line)
    pdf.set_font("helvetica", "", size)
    pdf.c_margin = CELL_PADDING
    for case in facts.cases:
        values = (
            latin1(case.label + (" *" if case.measured else "")),
            kg(case.total_kg),
            kg(case.rear_kg),
            ratio(case.lsf),
            limit_text(),
            signed(case.variance),
            "C" if case.compliant else "NC",
        )
        for width, align, value in zip(COLUMN_WIDTHS, COLUMN_ALIGN, values, strict=True):
            pdf.cell(width, row_h, value, border=1, align=align, new_x="RIGHT", new_y="TOP")
        pdf.ln(row_h)
    pdf.set_font("helvetica", "", 7.5)
    note = "C: compliant (LSF below 2/3). NC: not compliant. Variance = 2/3 - LSF. LSF = rear / total weight."
    if any(case.measured for case in facts.cases):
        note += " * weighed directly with the occupants or ballast aboard."
    pdf.cell(CONTENT_W, 4, note, new_x="LMARGIN", new_y="NEXT")


def _table_headings(pdf: FPDF, size: float, line: float) -> None:
    """The headings row: grey, bold, each heading wrapped within its column, two lines high."""
    pdf.set_font("helvetica", "B", size)
    height = 2 * line + 1.2
    top, x = pdf.get_y(), MARGIN
    pdf.set_fill_color(225, 225, 225)
    for width, align, heading in zip(COLUMN_WIDTHS, COLUMN_ALIGN, TABLE_HEADINGS, strict=True):
        pdf.rect(x, top, width, height, style="DF")
        pdf.set_xy(x + CELL_PADDING, top + 0.6)
        pdf.multi_cell(width - 2 * CELL_PADDING, line, heading, align=align, new_x="LEFT", new_y="NEXT")
        x += width
    pdf.set_xy(MARGIN, top + height)


def _chart_and_qr(pdf: FPDF, document: CertificateDocument) -> None:
    top = pdf.get_y() + 3
    pdf.set_font("helvetica", "B", 11)
    pdf.set_xy(MARGIN, top)
    pdf.cell(110, 6, "LSF per loading case against the limit 2/3")
    chart_top = top + 12
    chart_h = max(min(VALIDITY_Y - 12 - chart_top, 62), 24)
    draw_chart(pdf, Box(MARGIN + 12, chart_top, 100, chart_h), document.facts.cases)

    qr_size = 52.0  # modules of 0.85 mm (QR version 10) or more: see tests/certificates/test_qr_scan.py
    qr_x, qr_y = PAGE_W - MARGIN - qr_size, PAGE_H - MARGIN - qr_size - 16
    _draw_qr(pdf, document.qr_url, qr_x, qr_y, qr_size)
    pdf.set_xy(qr_x - 8, qr_y + qr_size + 1)
    pdf.set_font("helvetica", "", 7.5)
    pdf.multi_cell(
        qr_size + 8,
        3.4,
        latin1(f"Scan to verify, or visit {document.verify_url} and enter the number"),
        align="C",
    )

    pdf.set_xy(MARGIN, VALIDITY_Y)
    pdf.set_font("helvetica", "B", 10)
    validity = "Valid" if document.kind == "compliant" else "Refusal stands"
    pdf.cell(
        120,
        5,
        latin1(f"Issued {day(document.issued_at)}. {validity} until {day(document.expires_at)}."),
        new_x="LMARGIN",
        new_y="NEXT",
    )
    pdf.set_font("helvetica", "", 7.5)
    pdf.multi_cell(
        120,
        3.4,
        latin1(
            f"Decided under rules {document.facts.inspection.rules_version}: a loading case complies only if "
            "its LSF is below 2/3, decided exactly; figures are rounded for display."
        ),
        new_x="LMARGIN",
        new_y="NEXT",
    )


def _draw_qr(pdf: FPDF, data: str, x: float, y: float, size: float) -> None:
    """The QR code as filled vector squares, with its quiet zone."""
    # A fixed mask pattern: any of the eight decodes alike, and scoring all eight for the "best" one
    # (segno's default) costs four times the rest of the page.
    code = segno.make(data, error="m", boost_error=False, mask=QR_MASK)
    border = 2
    rows = [list(row) for row in code.matrix_iter(border=border)]
    module = size / len(rows)
    pdf.set_fill_color(255, 255, 255)
    pdf.rect(x, y, size, size, style="F")
    pdf.set_fill_color(0, 0, 0)
    fill = RenderStyle.F  # the enum itself: a string would be parsed again for each of ~1000 squares
    for r, row in enumerate(rows):
        c = 0
        while c < len(row):
            if not row[c]:
                c += 1
                continue
            start = c
            while c < len(row) and row[c]:
                c += 1
            pdf.rect(x + start * module, y + r * module, (c - start) * module, module, style=fill)
