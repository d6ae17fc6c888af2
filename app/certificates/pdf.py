"""The certificate (or refusal) as an A4 PDF with real, selectable text in an embedded Unicode font.

It opens with what it allows: a certificate with a black-framed "CERTIFIED: the driver and up to 2
passengers", a refusal with a solid red "NOT CERTIFIED: REFUSAL" band and what the vehicle may carry,
its pages framed in red. Rendered once when the document is issued; the bytes are stored and served
unchanged while it is in force (app/certificates/stamp.py stamps a copy once it is not). The text is set
in Noto Sans (app/documents/fonts.py), so Yoruba, Hausa and Igbo names print as written; every block
is measured before it is drawn (app/documents/layout.py), so long makes, models, station names and
many loading cases wrap or move to a second page instead of running into the QR code or the chart.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import datetime
from decimal import Decimal
from fractions import Fraction

import segno

from app.certificates.facts import CaseFacts, Facts, ReadingFacts
from app.documents.chart import SECOND_LINE, Box, chart_height, draw_chart
from app.documents.layout import (
    BOTTOM,
    CONTENT_W,
    MARGIN,
    PAGE_H,
    PAGE_W,
    Layout,
    Page,
    line_height,
    second_size,
)
from app.dynamics.pdf import draw_estimates
from app.i18n.active import current_locale, use_locale
from app.i18n.active import gettext as _
from app.i18n.locales import ENGLISH
from app.stability import LSF_LIMIT
from app.stability import Layout as AxleLayout
from app.web.formatting import NOT_RECORDED, fixed, kg, load_kg, local_time, long_date
from app.wording import (
    case_name,
    document_headline,
    document_title,
    occupancy_sentence,
    rear_weight_heading,
    rules_words,
    verdict_mark,
    verdict_sentence,
)

QR_BOX = 56.0  # mm: the QR code's white square, its quiet zone included
QR_SYMBOL = 48.0  # mm: the code itself (version 8 and up; a smaller version keeps 4 modules of quiet zone)
QR_QUIET = 4  # modules of quiet zone on each side, as the QR standard asks
QR_MASK = 1
REMEDIES_CHART_W = 72.0  # mm: a refusal's chart, with the remedies in the column beside it
NARROW_CHART_CASES = 7  # up to this many cases, the narrow chart keeps its case names apart
COMPACT_AFTER = 6  # more failing cases than this: the reasons in one paragraph
COLUMN_WIDTHS = (44.0, 24.0, 30.0, 20.0, 24.0, 20.0, 18.0)
COLUMN_ALIGN = ("L", "R", "R", "R", "R", "R", "C")
CELL_PADDING = 1.2  # mm left and right of the text in a table cell
LABEL_W = 31.0  # the label column of the vehicle and inspection particulars
HEADLINE_SIZE = 18.0  # pt: the opening block's "CERTIFIED: ..." or "NOT CERTIFIED: REFUSAL"
HEADLINE_PAD = 2.5  # mm inside the opening block's frame
HEADLINE_FRAME = 1.2  # mm: the opening block's frame
NUMBER_SIZE = 20.0  # pt: the document's number, in the embedded bold face (digits of equal width)
CERTIFIED_RGB = (0, 0, 0)
REFUSAL_RGB = (176, 0, 0)
PAGE_FRAME = 7.0  # mm from the edge: a refusal's red frame round every page
PAGE_FRAME_W = 1.0
MIN_PLACES, MAX_PLACES = 3, 6  # decimals of the LSF and its margins: enough never to contradict


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
    second_language: str | None = None  # printed under the English (ha, yo, ig, pcm); None: English only


def when(moment: datetime) -> str:
    """A time in the service's display zone: 23 Nov 2026, 15:05 WAT."""
    return local_time(moment)


def day(moment: datetime) -> str:
    """A date in the service's display zone: 23 November 2026."""
    return long_date(moment)


def title(kind: str) -> str:
    """The document's title for its kind."""
    return document_title(kind)


def places_for(cases: Sequence[CaseFacts], limit_value: Fraction = LSF_LIMIT) -> int:
    """The fewest decimals (3 or more) at which the LSFs and margins printed cannot contradict each other.

    At 3 decimals LSF 0.7004 and 0.6996 both print 0.700 while their margins print 0.034 and 0.033,
    and an LSF just above 2/3 prints as the limit itself: the document then prints one decimal more,
    for every case, until two cases print the same LSF only with the same margin and no LSF off the
    limit prints as the limit.
    """
    for places in range(MIN_PLACES, MAX_PLACES + 1):
        limit = fixed(limit_value, places)
        margins: dict[str, set[str]] = {}
        lsfs: dict[str, set[str]] = {}
        for case in cases:
            lsf, margin = fixed(case.lsf, places), fixed(case.variance, places)
            margins.setdefault(lsf, set()).add(margin)
            lsfs.setdefault(margin, set()).add(lsf)
        on_limit = any(fixed(c.lsf, places) == limit and c.variance != 0 for c in cases)
        if not on_limit and all(len(found) == 1 for found in (*margins.values(), *lsfs.values())):
            return places
    return MAX_PLACES


def limit_words(places: int, limit: Fraction = LSF_LIMIT) -> str:
    """The standard as the study prints it, to the document's decimals: 2/3 (0.667), a tadpole's 1/3."""
    return f"{limit.numerator}/{limit.denominator} ({fixed(limit, places)})"


def table_headings(layout: AxleLayout) -> tuple[str, ...]:
    """Table 4's headings: the rear axle's column says wheel or wheels, as the vehicle has."""
    return (
        _("Occupants"),
        _("Total weight (kg)"),
        rear_weight_heading(layout.name),
        _("Actual LSF"),
        _("Standard (max)"),
        _("Variance"),
        _("Result"),
    )


def binding_note() -> str:
    """What a bilingual paper says of its languages (in each of them)."""
    return _("The English text is the legally binding one.")


def wheel_name(wheel: str, stored: str) -> str:
    """A wheel's name on the paper: as stored (English), or its translation."""
    names = {
        "front_kg": _("Front wheel"),
        "left_front_kg": _("Left front wheel"),
        "right_front_kg": _("Right front wheel"),
        "left_rear_kg": _("Left rear wheel"),
        "right_rear_kg": _("Right rear wheel"),
        "rear_kg": _("Rear wheel"),
        "overall_kg": _("Overall weight"),
    }
    return stored if current_locale() == ENGLISH else names.get(wheel, stored)


def verdict_words(facts: Facts) -> str:
    """The verdict sentence: as the facts hold it in English, worded afresh in another language."""
    if current_locale() == ENGLISH:
        return facts.verdict
    return verdict_sentence([(c.occupants, c.compliant) for c in facts.cases], facts.max_compliant_occupants)


def occupancy_words(facts: Facts) -> str:
    """The occupancy sentence: as the facts hold it in English, worded afresh in another language."""
    if current_locale() == ENGLISH:
        return facts.occupancy
    return occupancy_sentence(facts.compliant, facts.max_compliant_occupants)


def signed_to(value: Decimal, places: int) -> str:
    """A variance with its sign: +0.009, -0.030."""
    text = fixed(value, places)
    return text if text.startswith("-") else f"+{text}"


def refusal_reason(case: CaseFacts, places: int = MIN_PLACES, limit_value: Fraction = LSF_LIMIT) -> str:
    """Why one loading case fails, and by how much."""
    excess = -case.variance
    name, lsf, limit = case_name(case.occupants), fixed(case.lsf, places), limit_words(places, limit_value)
    if excess == 0:
        return _("%(case)s: LSF %(lsf)s equals the limit %(limit)s; it must be below it.") % {
            "case": name,
            "lsf": lsf,
            "limit": limit,
        }
    return _("%(case)s: LSF %(lsf)s is above the limit %(limit)s by %(excess)s.") % {
        "case": name,
        "lsf": lsf,
        "limit": limit,
        "excess": fixed(excess, places),
    }


def render_pdf(document: CertificateDocument) -> bytes:
    """The certificate as PDF bytes; the same document always gives the same bytes."""
    return render_with_layout(document)[0]


def render_with_layout(document: CertificateDocument) -> tuple[bytes, Layout]:
    """The PDF bytes and where the layout put its graphics (for the geometry tests)."""
    # English first, whatever language the request that issues it is answered in.
    with use_locale(ENGLISH):
        return _render(document)


def _render(document: CertificateDocument) -> tuple[bytes, Layout]:
    facts = document.facts
    name = f"{title(document.kind)} {document.number}"
    if document.kind != "compliant":
        name = f"NOT CERTIFIED: {name}"
    pdf = Page(continued=f"{name} (continued)", second_language=document.second_language)
    pdf.set_creation_date(document.issued_at)
    pdf.set_title(f"{title(document.kind)} {document.number}")
    pdf.set_author(facts.authority)
    pdf.set_subject(f"{facts.vehicle.registration_number}: {facts.verdict}")
    pdf.set_creator("trikecert")
    pdf.set_lang("en")
    pdf.add_page()

    places = places_for(facts.cases, facts.axles.limit)
    _headline(pdf, document)
    _header(pdf, document)
    _particulars(pdf, facts)
    _readings(pdf, facts)
    _reasons_block(pdf, document, places)
    _table(pdf, facts, places)
    _chart(pdf, document)
    if facts.estimates is not None:
        draw_estimates(pdf, facts.estimates, facts.axles)
    pdf.page_lines(name)
    if document.kind != "compliant":
        _page_frames(pdf)
    pdf.layout.printable.report(document.number)
    return bytes(pdf.output()), pdf.layout


def _headline(pdf: Page, document: CertificateDocument) -> None:
    """The first thing on the page: what the paper allows, in a block a refusal cannot be mistaken for.

    A certificate's is framed in black on white; a refusal's is a solid red band with the words in
    white (still unlike a certificate's when photocopied in grey), and its pages are framed in red.
    """
    facts = document.facts
    refusal = document.kind != "compliant"
    inner = CONTENT_W - 2 * HEADLINE_PAD
    lines: list[tuple[str, float, bool]] = []
    for index, text in enumerate(
        pdf.both(lambda: document_headline(document.kind, facts.max_compliant_occupants))
    ):
        lines.append((text, HEADLINE_SIZE if index == 0 else second_size(HEADLINE_SIZE), True))
    if refusal:
        said, size, bold = (lambda: occupancy_words(facts)), 13.0, True
    else:
        said, size, bold = (lambda: verdict_words(facts)), 10.0, False
    for index, text in enumerate(pdf.both(said)):
        lines.append((text, size if index == 0 else second_size(size), bold))
    height = sum(pdf.measure(inner, text, size, bold) for text, size, bold in lines) + 2 * HEADLINE_PAD
    top = MARGIN
    if refusal:
        pdf.set_fill_color(*REFUSAL_RGB)
        pdf.rect(MARGIN, top, CONTENT_W, height, style="F")
        pdf.set_text_color(255, 255, 255)
    else:
        pdf.set_draw_color(*CERTIFIED_RGB)
        pdf.set_line_width(HEADLINE_FRAME)
        half = HEADLINE_FRAME / 2  # the frame drawn inside the block's box
        pdf.rect(MARGIN + half, top + half, CONTENT_W - HEADLINE_FRAME, height - HEADLINE_FRAME, style="D")
    y = top + HEADLINE_PAD
    for text, size, bold in lines:
        y = pdf.box(MARGIN + HEADLINE_PAD, y, inner, text, size, bold=bold)
    pdf.set_text_color(0, 0, 0)
    pdf.region("headline", MARGIN, top, CONTENT_W, height)
    pdf.set_line_width(0.2)
    pdf.set_draw_color(0, 0, 0)
    pdf.set_xy(MARGIN, top + height)


def _header(pdf: Page, document: CertificateDocument) -> None:
    left_w = CONTENT_W - QR_BOX - 6
    # The QR code's white square (its quiet zone) stands right under the opening block; the text
    # beside it a little lower, level with the code itself.
    qr_top = pdf.get_y() + 0.5
    top = qr_top + 2.5
    compliant = document.kind == "compliant"
    address = {"verify": document.verify_url, "record": f"{document.verify_url}/{document.number}"}
    y = pdf.box(MARGIN, top, left_w, document.facts.authority, 11, bold=True)
    y = pdf.words(MARGIN, y, left_w, lambda: title(document.kind), 20, bold=True)
    y = pdf.words(MARGIN, y, left_w, lambda: _("Certificate number") if compliant else _("Refusal number"), 9)
    y = pdf.box(MARGIN, y, left_w, document.number, NUMBER_SIZE, bold=True)

    def dated() -> str:
        dates = {"issued": day(document.issued_at), "until": day(document.expires_at)}
        if compliant:
            return _("Issued %(issued)s. Valid until %(until)s.") % dates
        return _("Issued %(issued)s. Refusal stands until %(until)s.") % dates

    y = pdf.words(MARGIN, y, left_w, dated, 10, bold=True)
    y = pdf.words(
        MARGIN,
        y,
        left_w,
        lambda: (
            _(
                "This paper shows the record as issued. Whether it is still in force (or was revoked, "
                "superseded, or has expired) is at %(record)s"
            )
            % address
        ),
        8.5,
    )
    y = pdf.words(
        MARGIN,
        y,
        left_w,
        lambda: _("Scan to verify, or visit %(verify)s and enter the number") % address,
        8.5,
    )
    if pdf.second_language is not None:
        y = pdf.words(MARGIN, y, left_w, binding_note, 8.5, bold=True)
    draw_qr(pdf, document.qr_url, PAGE_W - MARGIN - QR_BOX, qr_top, QR_BOX)
    bottom = max(y + 2, qr_top + QR_BOX + 0.5)
    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.5)
    pdf.line(MARGIN, bottom, PAGE_W - MARGIN, bottom)
    pdf.set_line_width(0.2)
    pdf.set_xy(MARGIN, bottom + 3)


def _page_frames(pdf: Page) -> None:
    """A refusal's red frame round every page, so no page of it passes for a certificate's."""
    pages = pdf.page
    for page in range(1, pages + 1):
        pdf.page = page
        pdf.set_draw_color(*REFUSAL_RGB)
        pdf.set_line_width(PAGE_FRAME_W)
        pdf.rect(PAGE_FRAME, PAGE_FRAME, PAGE_W - 2 * PAGE_FRAME, PAGE_H - 2 * PAGE_FRAME, style="D")
    pdf.page = pages
    pdf.set_line_width(0.2)
    pdf.set_draw_color(0, 0, 0)


Say = Callable[[], str]


def _fixed(value: str) -> Say:
    """A value printed as it is in every language (a plate, a make, a number)."""
    return lambda: value


def _particulars(pdf: Page, facts: Facts) -> None:
    vehicle, inspection = facts.vehicle, facts.inspection
    occupant = {"id": inspection.id, "mass": kg(inspection.occupant_mass_kg)}
    columns: tuple[tuple[float, float, Say, list[tuple[Say, Say]]], ...] = (
        (
            MARGIN,
            86.0,
            lambda: _("Vehicle"),
            [
                (lambda: _("Registration"), _fixed(vehicle.registration_number)),
                (lambda: _("Make"), _fixed(vehicle.make)),
                (lambda: _("Model"), _fixed(vehicle.model)),
                (lambda: _("Year"), _fixed(str(vehicle.model_year) if vehicle.model_year else NOT_RECORDED)),
                (lambda: _("Chassis number"), _fixed(vehicle.chassis_number or NOT_RECORDED)),
            ],
        ),
        (
            MARGIN + 92,
            CONTENT_W - 92,
            lambda: _("Inspection"),
            [
                (lambda: _("Station"), _fixed(inspection.station or NOT_RECORDED)),
                (lambda: _("Scale calibration"), _fixed(facts.calibration)),
                (lambda: _("Date and time"), _fixed(when(inspection.weighed_at))),
                (lambda: _("Inspection"), lambda: _("no. %(id)s; occupant %(mass)s kg") % occupant),
            ],
        ),
    )
    top = pdf.get_y()
    bottoms = []
    for x, width, heading, rows in columns:
        y = pdf.words(x, top, width, heading, 11, bold=True)
        for label, value in rows:
            below_label = pdf.words(x, y, LABEL_W - 1, label, 9)
            below_value = pdf.words(x + LABEL_W, y, width - LABEL_W, value, 9, bold=True)
            y = max(below_label, below_value)
        bottoms.append(y)
    # Who stands behind it: one full-width line (in a column each name and badge would wrap).
    people = {"recorded": facts.recorded_by, "issuer": facts.issuer}
    y = pdf.words(
        MARGIN,
        max(bottoms) + 1.5,
        CONTENT_W,
        lambda: _("Recorded by %(recorded)s. Issued by %(issuer)s.") % people,
        9,
    )
    pdf.set_xy(MARGIN, y + 3)


def reading_words(reading: ReadingFacts) -> str:
    """One wheel's averaged reading, and how often it was read."""
    figures = {
        "wheel": wheel_name(reading.wheel, reading.name),
        "mean": kg(reading.mean_kg),
        "count": reading.count,
        "spread": kg(reading.spread_kg),
    }
    if reading.count == 1:
        return _("%(wheel)s: %(mean)s kg (read once)") % figures
    return _("%(wheel)s: %(mean)s kg (read %(count)s times, spread %(spread)s kg)") % figures


def _readings(pdf: Page, facts: Facts) -> None:
    half = (CONTENT_W - 4) / 2
    says: list[Say] = [lambda r=reading: reading_words(r) for reading in facts.readings]  # type: ignore[misc]
    rows = [says[i : i + 2] for i in range(0, len(says), 2)]
    title_h = pdf.measure_words(CONTENT_W, lambda: _("Averaged readings"), 11, bold=True)
    height = title_h + sum(max(pdf.measure_words(half, say, 9) for say in row) for row in rows)
    pdf.room(height)
    y = pdf.words(MARGIN, pdf.get_y(), CONTENT_W, lambda: _("Averaged readings"), 11, bold=True)
    for row in rows:
        y = max(pdf.words(MARGIN + i * (half + 4), y, half, say, 9) for i, say in enumerate(row))
    pdf.set_xy(MARGIN, y + 2)


def _reasons(facts: Facts, places: int) -> list[tuple[Say, float]]:
    failing = facts.failing_cases
    limit = facts.axles.limit
    if len(failing) <= COMPACT_AFTER:
        return [(lambda c=case: f"- {refusal_reason(c, places, limit)}", 8.5) for case in failing]  # type: ignore[misc]

    def compact() -> str:
        text = "; ".join(
            _("%(case)s: LSF %(lsf)s, %(excess)s over")
            % {
                "case": case_name(c.occupants),
                "lsf": fixed(c.lsf, places),
                "excess": fixed(-c.variance, places),
            }
            for c in failing
        )
        return _("Limit %(limit)s. %(reasons)s.") % {"limit": limit_words(places, limit), "reasons": text}

    return [(compact, 8)]


def _reasons_block(pdf: Page, document: CertificateDocument, places: int) -> None:
    """A refusal's verdict and reasons: each failing case and by how much."""
    facts = document.facts
    if document.kind == "compliant":
        return

    def heading() -> str:
        return _("%(verdict)s Reasons for refusal (cases that fail and by how much):") % {
            "verdict": verdict_words(facts)
        }

    blocks: list[tuple[Say, float, bool]] = [(heading, 8.5, True)]
    blocks += [(say, size, False) for say, size in _reasons(facts, places)]
    pdf.room(sum(pdf.measure_words(CONTENT_W, say, size, bold) for say, size, bold in blocks))
    y = pdf.get_y()
    for say, size, bold in blocks:
        y = pdf.words(MARGIN, y, CONTENT_W, say, size, bold=bold)
    pdf.set_xy(MARGIN, y + 2)


def _row(case: CaseFacts, places: int, limit: Fraction = LSF_LIMIT) -> tuple[str, ...]:
    return (
        case_name(case.occupants) + (" *" if case.measured else ""),
        load_kg(case.total_kg),
        load_kg(case.rear_kg),
        fixed(case.lsf, places),
        limit_words(places, limit),
        signed_to(case.variance, places),
        verdict_mark(case.compliant),
    )


def _table(pdf: Page, facts: Facts, places: int) -> None:
    # Plain bordered cells: fpdf2's table() lays out every cell as a multi-line box, which cost a
    # third of the page's rendering time for rows that are always one line.
    size = 9.0 if len(facts.cases) <= COMPACT_AFTER else 8.0
    rows = [_row(case, places, facts.axles.limit) for case in facts.cases]
    # A bilingual paper names each case again, under the English, in the second language.
    names = [pdf.both(lambda c=case: case_name(c.occupants))[1:] for case in facts.cases]  # type: ignore[misc]
    bilingual = any(names)
    pdf.style(size)
    widest = max(
        pdf.get_string_width(value) / (width - 2 * CELL_PADDING)
        for row in rows
        for value, width in zip(row, COLUMN_WIDTHS, strict=True)
    )
    first = COLUMN_WIDTHS[0] - 2 * CELL_PADDING
    scale = second_size(size) / size
    widest = max([widest, *(pdf.get_string_width(n) * scale / first for found in names for n in found)])
    size = min(size, size / widest)  # shrink the table's text until its widest cell fits
    row_h = line_height(size) + 0.8 + (line_height(second_size(size)) if bilingual else 0)
    headings: list[Say] = [lambda i=i: table_headings(facts.axles)[i] for i in range(len(COLUMN_WIDTHS))]  # type: ignore[misc]
    heading_h = max(
        pdf.measure_words(width - 2 * CELL_PADDING, say, size, bold=True)
        for width, say in zip(COLUMN_WIDTHS, headings, strict=True)
    )
    limit = facts.axles.limit_text
    measured = any(case.measured for case in facts.cases)

    def note() -> str:
        text = _(
            "C: compliant (LSF below %(limit)s). NC: not compliant. Variance = %(limit)s - LSF. "
            "LSF = rear / total weight."
        ) % {"limit": limit}
        if measured:
            text += " " + _("* weighed directly with the occupants or ballast aboard.")
        return text

    def title() -> str:
        return _("Loading cases (Table 4 of the study)")

    note_h = pdf.measure_words(CONTENT_W, note, 7.5)
    title_h = pdf.measure_words(CONTENT_W, title, 11, bold=True)
    pdf.room(title_h + heading_h + 1.2 + row_h * len(rows) + note_h)
    top = pdf.words(MARGIN, pdf.get_y(), CONTENT_W, title, 11, bold=True)
    x = MARGIN
    pdf.set_fill_color(225, 225, 225)
    pdf.set_draw_color(0, 0, 0)
    for width, align, say in zip(COLUMN_WIDTHS, COLUMN_ALIGN, headings, strict=True):
        pdf.rect(x, top, width, heading_h + 1.2, style="DF")
        pdf.words(x + CELL_PADDING, top + 0.6, width - 2 * CELL_PADDING, say, size, bold=True, align=align)
        x += width
    y = top + heading_h + 1.2
    pdf.style(size)
    pdf.c_margin = CELL_PADDING
    for row, translated in zip(rows, names, strict=True):
        pdf.set_xy(MARGIN, y)
        for index, (width, align, value) in enumerate(zip(COLUMN_WIDTHS, COLUMN_ALIGN, row, strict=True)):
            # A bilingual paper's case name is set below, in two lines: its cell is drawn empty.
            shown = "" if bilingual and index == 0 else pdf.printable(value)
            pdf.cell(width, row_h, shown, border=1, align=align, new_x="RIGHT", new_y="TOP")
        if bilingual:
            below = pdf.box(MARGIN + CELL_PADDING, y + 0.4, first, row[0], size)
            for text in translated:
                pdf.box(MARGIN + CELL_PADDING, below, first, text, second_size(size))
            pdf.style(size)
            pdf.c_margin = CELL_PADDING
        y += row_h
    pdf.c_margin = 0
    y = pdf.words(MARGIN, y + 0.5, CONTENT_W, note, 7.5)
    pdf.set_xy(MARGIN, y)


def _chart(pdf: Page, document: CertificateDocument) -> None:
    """The chart, and beside it the rules the verdict was decided under."""
    limit = {"limit": document.facts.axles.limit_text}

    def words() -> str:
        return _("LSF per loading case against the limit %(limit)s") % limit

    heading = pdf.measure_words(120, words, 11, bold=True) + 1
    if pdf.second_language is not None:
        heading += 2 * SECOND_LINE  # the chart's legend and axis title, each a line more
    height = chart_height(BOTTOM - pdf.get_y() - 3 - heading)
    if height is None:
        pdf.new_page()
        height = chart_height(BOTTOM - pdf.get_y() - 3 - heading)
        assert height is not None
    refusal = document.kind == "refusal" and bool(document.facts.remedies_sentence)
    top = pdf.words(MARGIN, pdf.get_y() + 3, 120, words, 11, bold=True)
    # A refusal's remedies stand beside a narrower chart, under the rules, so the page stays one page.
    narrow = refusal and len(document.facts.cases) <= NARROW_CHART_CASES
    width = REMEDIES_CHART_W if narrow else 100
    box = Box(MARGIN + 12, top + 1, width, height)
    area = draw_chart(pdf, box, document.facts.cases, limit=document.facts.axles.limit, say=pdf.both)
    pdf.region("chart", *area)

    def rules() -> str:
        return _("Decided exactly under the rule: %(rule)s; the figures are rounded for display.") % {
            "rule": rules_words(document.facts.inspection.rules_version)
        }

    beside = area[0] + area[2] + 4
    column = PAGE_W - MARGIN - beside
    y = pdf.words(beside, area[1] + 6, column, rules, 7.5)
    chart_bottom = area[1] + area[3]
    # What follows starts below the chart and below the words beside it, which a translation can
    # make the taller of the two.
    below = max(chart_bottom, y)
    if refusal:

        def paragraph() -> str:
            return _("What would make it comply: %(remedies)s") % {
                "remedies": document.facts.remedies_sentence
            }

        if y + 2 + pdf.measure_words(column, paragraph, 7.5) <= chart_bottom:
            pdf.words(beside, y + 2, column, paragraph, 7.5)
        else:
            pdf.set_xy(MARGIN, below + 2)
            pdf.room(pdf.measure_words(CONTENT_W, paragraph, 8.5))
            below = pdf.words(MARGIN, pdf.get_y(), CONTENT_W, paragraph, 8.5)
    pdf.set_xy(MARGIN, below + 3)


def draw_qr(pdf: Page, data: str, x: float, y: float, size: float) -> None:
    """The QR code, QR_SYMBOL mm wide, centred in a white `size` mm square (its quiet zone)."""
    # A fixed mask pattern: any of the eight decodes alike, and scoring all eight for the "best" one
    # (segno's default) costs four times the rest of the page.
    code = segno.make(data, error="m", boost_error=False, mask=QR_MASK)
    rows = [list(row) for row in code.matrix_iter(border=0)]
    # The code prints QR_SYMBOL mm wide whatever its version, centred in the white square; a version
    # too small for that keeps the standard's 4 modules of quiet zone and prints smaller.
    module = min(QR_SYMBOL / len(rows), size / (len(rows) + 2 * QR_QUIET))
    x0 = y0 = (size - module * len(rows)) / 2
    pdf.region("qr", x, y, size, size)
    pdf.set_fill_color(255, 255, 255)
    pdf.rect(x, y, size, size, style="F")
    x, y = x + x0, y + y0
    # One path of a rectangle per run of dark modules, filled once: a call of fpdf2's rect() per run
    # (about 1,500 of them) cost as much as the rest of the page.
    k, top = pdf.k, pdf.h
    runs = []
    for r, row in enumerate(rows):
        c = 0
        while c < len(row):
            if not row[c]:
                c += 1
                continue
            start = c
            while c < len(row) and row[c]:
                c += 1
            runs.append(
                f"{(x + start * module) * k:.3f} {(top - y - r * module) * k:.3f} "
                f"{(c - start) * module * k:.3f} {-module * k:.3f} re"
            )
    pdf.draw_raw("q 0 g\n" + "\n".join(runs) + "\nf Q")
