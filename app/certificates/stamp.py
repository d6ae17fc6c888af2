"""A document no longer in force, as downloaded: the stored original with a stamp across every page.

The stamp is drawn at download time from the record (the revocation's date and reason, the newer
document's number and date, or the expiry) and added to a copy of the stored bytes as a PDF
incremental update. The stored original is never changed: its bytes open the stamped file exactly
as stored (so their SHA-256 still matches the record), and a reader shows the last revision, with
the stamp. Re-rendering the document with a stamp layer would instead print today's wording and
fonts, not the paper that was issued.

On every page the stamp puts a red band in the top margin with the status, its date and its
detail (one line: a longer reason is cut short with an ellipsis, and the line under it says where
the record is, reason in full), a large diagonal word ("REVOKED") across the page, translucent so
the original stays readable underneath, and a red frame round the page; a certificate's opening
"CERTIFIED: ..." is struck through. Nothing of the original is hidden.
"""

from __future__ import annotations

import hashlib
import io
import math
import unicodedata
from dataclasses import dataclass
from datetime import UTC, datetime

from fpdf import FPDF
from fpdf.enums import TextMode
from pypdf import PdfReader, PdfWriter

from app.certificates.models import Certificate
from app.certificates.pdf import HEADLINE_PAD
from app.certificates.pdf import HEADLINE_SIZE as OPENING_SIZE
from app.certificates.records import Status
from app.documents import fonts
from app.documents.layout import CONTENT_W, FOOT, MARGIN, PAGE_H, PAGE_W, Page, line_height
from app.i18n.active import N_, use_locale
from app.i18n.active import gettext as _
from app.i18n.locales import ENGLISH
from app.web.formatting import long_date
from app.wording import document_kind, status_headline_on

STAMP_RGB = (176, 0, 0)
BAND_TOP = 5.0  # mm: the band fills the top margin, clear of the edge a printer cannot print
BAND_PAD = 0.6
BAND_SIZE = 10.5
DETAIL_SIZE = 7.5
MAX_HEADLINE_LINES = 1  # a longer reason is cut with an ellipsis: the full text is on the verify page
DIAGONAL_SIZE = 110.0  # pt: the word across the page
DIAGONAL_OPACITY = 0.3  # the letters' fill: the text under them stays readable
OUTLINE_OPACITY = 0.7  # their outline, so the word stands out even where the page is busy
FRAME = 4.0  # mm from the edge: a red frame round every page, outside the document's own
FRAME_W = 1.5
CERTIFIED = "CERTIFIED:"  # how a certificate's opening block begins (wording.document_headline)
STRIKE_AT = 0.45  # of the opening line's height: through the middle of its capitals
STRIKE_W = 1.4  # mm
ELLIPSIS = "\u2026"
NOT_IN_FORCE = N_("Not in force: do not rely on this paper.")
FOOT_BAND_SIZE = 7.0  # pt: a bilingual paper's band at the foot, below the page line, in its second language
STAMP_EPOCH = datetime(2026, 1, 1, tzinfo=UTC)


@dataclass(frozen=True)
class Stamp:
    """What the stamp says: the status word, its headline (date and detail) and the line under it."""

    status: Status
    word: str
    headline: str
    detail: str
    second_word: str | None = None  # a bilingual paper's status word in its second language
    second_line: str | None = None  # and the band's words in it (a band at the foot of the page)

    def etag(self, original_sha256: str) -> str:
        """An ETag for the stamped file, from the original's hash and the stamp's words."""
        said = (self.headline, self.detail, *([self.second_line] if self.second_line else []))
        text = "\n".join((original_sha256, *said))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


def stamp_of(certificate: Certificate, status: Status, verify_address: str) -> Stamp | None:
    """The stamp for a document's status now, worded from the record; None while it is in force."""
    with use_locale(ENGLISH):
        headline = _headline(certificate, status)
    if headline is None:
        return None
    detail = f"Not in force: do not rely on this paper. The record: {verify_address}/{certificate.number}"
    second_word = second_line = None
    if certificate.second_language is not None:
        with use_locale(certificate.second_language):
            translated = status_word(status)
            said = unicodedata.normalize("NFC", f"{_(NOT_IN_FORCE)} {_headline(certificate, status)}")
        second_word = None if translated == status.upper() else translated
        second_line = None if said == f"{NOT_IN_FORCE} {headline}" else said
    return Stamp(
        status=status,
        word=status.upper(),
        headline=headline,
        detail=detail,
        second_word=second_word,
        second_line=second_line,
    )


def _headline(certificate: Certificate, status: Status) -> str | None:
    """The band's first line in the active language: the status, its date and what it is about."""
    kind = certificate.kind
    if status == "revoked" and certificate.revocation is not None:
        revocation = certificate.revocation
        since = long_date(revocation.revoked_at)
        return f"{status_headline_on(kind, status, since)}: {' '.join(revocation.reason.split())}"
    if status == "superseded" and certificate.superseded_by is not None:
        newer = certificate.superseded_by
        since = long_date(newer.issued_at)
        return _("%(headline)s by %(kind)s %(number)s") % {
            "headline": status_headline_on(kind, status, since),
            "kind": document_kind(newer.kind),
            "number": newer.number,
        }
    if status == "expired":
        return status_headline_on(kind, status, long_date(certificate.expires_at))
    return None


def status_word(status: Status) -> str:
    """The word across a paper no longer in force, in the active language (a bilingual paper's second)."""
    words = {"revoked": _("REVOKED"), "superseded": _("SUPERSEDED"), "expired": _("EXPIRED")}
    return words.get(status, status.upper())


def stamped_pdf(original: bytes, stamp: Stamp) -> bytes:
    """The stored PDF with `stamp` over every page, appended as an incremental update."""
    writer = PdfWriter(io.BytesIO(original), incremental=True)
    # A paper that opens "CERTIFIED: ..." (those issued since the opening block) has that line
    # struck through on its first page.
    struck = writer.pages[0].extract_text().lstrip().startswith(CERTIFIED)
    overlays = PdfReader(io.BytesIO(_overlay(stamp, struck))).pages
    for number, page in enumerate(writer.pages):
        page.merge_page(overlays[0 if number == 0 else -1])
        page.compress_content_streams()
    out = io.BytesIO()
    writer.write(out)
    return out.getvalue()


def _overlay(stamp: Stamp, struck: bool) -> bytes:
    """The stamp on A4 pages of its own, in the documents' embedded font: the first page's (with
    the opening line struck through when `struck`), then the other pages'."""
    pdf = Page(continued="")
    pdf.set_creation_date(STAMP_EPOCH)  # only the pages are used; a fixed date keeps the bytes the same
    for first in (True, False):
        pdf.add_page()
        pdf.set_draw_color(*STAMP_RGB)
        pdf.set_line_width(FRAME_W)
        pdf.rect(FRAME, FRAME, PAGE_W - 2 * FRAME, PAGE_H - 2 * FRAME, style="D")
        _band(pdf, stamp)
        if stamp.second_line is not None:
            _foot_band(pdf, stamp.second_line)
        _diagonal(pdf, stamp.word, stamp.second_word)
        if first and struck:
            _strike(pdf)
    return bytes(pdf.output())


def _strike(pdf: Page) -> None:
    """A red line through the opening block's first line ("CERTIFIED: ...")."""
    y = MARGIN + HEADLINE_PAD + line_height(OPENING_SIZE) * STRIKE_AT
    pdf.set_draw_color(*STAMP_RGB)
    pdf.set_line_width(STRIKE_W)
    pdf.line(MARGIN + HEADLINE_PAD - 1, y, PAGE_W - MARGIN - HEADLINE_PAD + 1, y)


def headline_lines(pdf: Page, headline: str) -> list[str]:
    """The headline wrapped in the band, at most MAX_HEADLINE_LINES, the last cut with an ellipsis."""
    width = CONTENT_W - 2 * BAND_PAD
    lines = pdf.lines(width, headline, BAND_SIZE, bold=True)
    if len(lines) <= MAX_HEADLINE_LINES:
        return lines
    kept = lines[: MAX_HEADLINE_LINES - 1]
    last = lines[MAX_HEADLINE_LINES - 1]
    while last and len(pdf.lines(width, last + ELLIPSIS, BAND_SIZE, bold=True)) > 1:
        last = last[:-1].rstrip()
    return [*kept, last + ELLIPSIS]


def _band(pdf: Page, stamp: Stamp) -> None:
    """The red band in the top margin: the status with its date and detail, and where the record is."""
    lines = headline_lines(pdf, stamp.headline)
    width = CONTENT_W - 2 * BAND_PAD
    height = (
        len(lines) * line_height(BAND_SIZE) + pdf.measure(width, stamp.detail, DETAIL_SIZE) + 2 * BAND_PAD
    )
    pdf.set_fill_color(*STAMP_RGB)
    pdf.rect(MARGIN, BAND_TOP, CONTENT_W, height, style="F")
    pdf.set_text_color(255, 255, 255)
    y = BAND_TOP + BAND_PAD
    for line in lines:
        y = pdf.box(MARGIN + BAND_PAD, y, width, line, BAND_SIZE, bold=True)
    pdf.box(MARGIN + BAND_PAD, y, width, stamp.detail, DETAIL_SIZE)
    pdf.set_text_color(0, 0, 0)


def _foot_band(pdf: Page, said: str) -> None:
    """A bilingual paper's band words in its second language: one red line at the foot of the page,
    between the page line and the frame (the top band's margin has room for the English only)."""
    width = CONTENT_W - 2 * BAND_PAD
    lines = pdf.lines(width, said, FOOT_BAND_SIZE, bold=True)
    line = lines[0]
    if len(lines) > 1:
        while line and len(pdf.lines(width, line + ELLIPSIS, FOOT_BAND_SIZE, bold=True)) > 1:
            line = line[:-1].rstrip()
        line += ELLIPSIS
    top = PAGE_H - FOOT + 0.2  # just below the page line (layout.page_lines)
    pdf.set_fill_color(*STAMP_RGB)
    pdf.rect(MARGIN, top, CONTENT_W, line_height(FOOT_BAND_SIZE) + 2 * BAND_PAD, style="F")
    pdf.set_text_color(255, 255, 255)
    pdf.box(MARGIN + BAND_PAD, top + BAND_PAD, width, line, FOOT_BAND_SIZE, bold=True)
    pdf.set_text_color(0, 0, 0)


def _diagonal(pdf: FPDF, word: str, second: str | None = None) -> None:
    """The status word, large, from the bottom left to the top right of the page (and, on a
    bilingual paper, its translation in smaller letters just below it, along the same line)."""
    pdf.set_font(fonts.FAMILY, "B", DIAGONAL_SIZE)
    angle = math.degrees(math.atan2(PAGE_H, PAGE_W))
    size = DIAGONAL_SIZE
    diagonal = math.hypot(PAGE_W, PAGE_H) * 0.78
    while pdf.get_string_width(word) > diagonal:
        size -= 4
        pdf.set_font(fonts.FAMILY, "B", size)
    width = pdf.get_string_width(word)
    cx, cy = PAGE_W / 2, PAGE_H / 2
    cap = size * 25.4 / 72 * 0.714  # Noto Sans' capital height, so the word is centred on the page
    if second is not None:
        _second_diagonal(pdf, second, angle, diagonal, cx, cy + cap / 2 + 6)
        pdf.set_font(fonts.FAMILY, "B", size)
    pdf.set_text_color(*STAMP_RGB)
    pdf.set_draw_color(*STAMP_RGB)
    pdf.set_line_width(0.5)
    with (
        pdf.local_context(
            fill_opacity=DIAGONAL_OPACITY, stroke_opacity=OUTLINE_OPACITY, text_mode=TextMode.FILL_STROKE
        ),
        pdf.rotation(angle, cx, cy),
    ):
        pdf.text(cx - width / 2, cy + cap / 2, word)
    pdf.set_text_color(0, 0, 0)


def _second_diagonal(pdf: FPDF, word: str, angle: float, diagonal: float, cx: float, below: float) -> None:
    """A bilingual paper's status word in its second language, under the English along the diagonal."""
    size = DIAGONAL_SIZE * 0.4
    pdf.set_font(fonts.FAMILY, "B", size)
    while pdf.get_string_width(word) > diagonal and size > 12:
        size -= 2
        pdf.set_font(fonts.FAMILY, "B", size)
    cap = size * 25.4 / 72 * 0.714
    pdf.set_text_color(*STAMP_RGB)
    pdf.set_draw_color(*STAMP_RGB)
    pdf.set_line_width(0.3)
    with (
        pdf.local_context(
            fill_opacity=DIAGONAL_OPACITY, stroke_opacity=OUTLINE_OPACITY, text_mode=TextMode.FILL_STROKE
        ),
        pdf.rotation(angle, cx, PAGE_H / 2),
    ):
        shaped = fonts.needs_shaping(word)  # a tone mark over a dotted capital (Yoruba's RỌ́PÒ)
        if shaped:
            pdf.set_text_shaping(True)
        pdf.text(cx - pdf.get_string_width(word) / 2, below + cap, word)
        if shaped:
            pdf.set_text_shaping(False)
    pdf.set_text_color(0, 0, 0)
