"""Measured layout on A4 for the certificate: text wraps inside its box, blocks move to a new page.

Every block is measured before it is drawn; one that does not fit below the cursor starts a new
page. Line heights are 1.45 times the font size, more than Noto Sans' ascent plus descent (1.36),
so the boxes of two lines never overlap. Graphics (the QR code, the chart) are recorded as regions,
which the layout keeps clear of text and the tests check against the text read back.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

from fpdf import FPDF
from fpdf.drawing_primitives import DeviceGray
from fpdf.line_break import Fragment

from app.documents import fonts
from app.i18n.active import gettext as _
from app.i18n.active import use_locale
from app.i18n.locales import ENGLISH

MARGIN = 15.0
PAGE_W = 210.0
PAGE_H = 297.0
CONTENT_W = PAGE_W - 2 * MARGIN
FOOT = 10.0  # the bottom margin, below the page line
FOOTER_H = 6.0  # the page line (number, page i of n) at the foot of every page
BOTTOM = PAGE_H - FOOT - FOOTER_H
LEADING = 1.45
PT = 25.4 / 72  # mm per point
SECOND_SCALE = 0.82  # a bilingual paper's translation: this much of its English line's size
SECOND_MIN = 6.5  # pt: never smaller than this
SECOND_RGB = (64, 64, 64)  # a translation's colour on white: lighter than the English, still dark
BLACK = DeviceGray(0)


def line_height(size: float) -> float:
    """The distance between two lines of text of `size` points (mm)."""
    return round(size * PT * LEADING, 3)


def second_size(size: float) -> float:
    """The size (pt) a translation is set at under an English line of `size` points."""
    return max(SECOND_MIN, round(size * SECOND_SCALE, 2))


@dataclass(frozen=True)
class Region:
    """A graphic on a page that no text may cross (mm from the top left)."""

    kind: str
    page: int
    x: float
    y: float
    w: float
    h: float


@dataclass
class Layout:
    """What the layout placed besides text: the graphic regions, and the characters it had to replace."""

    regions: list[Region] = field(default_factory=list)
    printable: fonts.Printable = field(default_factory=fonts.Printable)


class Page(FPDF):
    """fpdf2 with the embedded font, measured text boxes and a cursor that breaks pages."""

    def __init__(self, continued: str, second_language: str | None = None) -> None:
        super().__init__(orientation="portrait", unit="mm", format="A4")
        self.layout = Layout()
        self.continued = continued
        # A bilingual paper (like the Welsh MOT certificate): each English line, then its translation.
        self.second_language = second_language
        self._embedded = fonts.install(self)
        self.set_auto_page_break(auto=False)
        self.set_margins(MARGIN, MARGIN, MARGIN)
        self.c_margin = 0
        self.alias_nb_pages(None)  # type: ignore[arg-type]  # a make written "{nb}" prints as written
        self._wrapped: dict[tuple[float, str, float, bool], list[str]] = {}

    def output(self, *args: Any, **kwargs: Any) -> Any:
        """The PDF (see FPDF.output), each embedded font first cut down to the glyphs used."""
        for font in self._embedded:
            fonts.cut(font)
        return super().output(*args, **kwargs)

    def style(self, size: float, bold: bool = False) -> None:
        """Set the embedded font at `size` points."""
        self.set_font(fonts.FAMILY, "B" if bold else "", size)

    def printable(self, text: str) -> str:
        """The text as the font can draw it (see fonts.Printable)."""
        return self.layout.printable(text)

    def lines(self, width: float, text: str, size: float, bold: bool = False) -> list[str]:
        """`text` broken into lines no wider than `width` mm at `size` points, at spaces if it can."""
        key = (width, text, size, bold)
        if key not in self._wrapped:
            widths = fonts.widths("B" if bold else "")
            per_unit = size * PT / 1000

            def wide(part: str) -> float:
                return sum(widths[ord(char)] for char in part) * per_unit

            self._wrapped[key] = _wrap(self.printable(text), width, wide)
        return self._wrapped[key]

    def measure_line(self, line: str, size: float, bold: bool = False) -> float:
        """The width (mm) of one line at `size` points (combining accents take no room)."""
        widths = fonts.widths("B" if bold else "")
        return sum(widths.get(ord(char), 0) for char in self.printable(line)) * size * PT / 1000

    def measure(self, width: float, text: str, size: float, bold: bool = False) -> float:
        """The height (mm) of `text` wrapped in `width` at `size` points."""
        return len(self.lines(width, text, size, bold)) * line_height(size)

    def box(
        self, x: float, y: float, width: float, text: str, size: float, bold: bool = False, align: str = "L"
    ) -> float:
        """Draw `text` wrapped in `width` from (x, y); returns the y below it."""
        height = line_height(size)
        self.style(size, bold)
        for line in self.lines(width, text, size, bold):
            shaped = self._shaping(line)
            self.set_xy(x, y)
            if shaped:
                # A raised accent sits above its letter's baseline, and text extractors (poppler,
                # pdfium) would read it as a line of its own: the line's text is given as ActualText.
                self._out(f"/Span <</ActualText <FEFF{line.encode('utf-16-be').hex().upper()}>>> BDC")
            if shaped and align in ("R", "C"):
                # fpdf2 misplaces the combining accents of a shaped line it aligns itself (they drift
                # right, out of the cell): the line is placed here and drawn left-aligned.
                wide = self.measure_line(line, size, bold)
                self.set_x(x + (width - wide) / (2 if align == "C" else 1))
                self.cell(wide, height, line, align="L")
            else:
                self.cell(width, height, line, align=align)
            if shaped:
                self._out("EMC")
            y += height
        self._shaping("")
        return y

    def _parse_chars(
        self,
        text: str,
        markdown: bool,
        *,
        _initial_emphasis: tuple[bool, bool, bool, bool] | None = None,
    ) -> Iterator[Fragment]:
        # fpdf2 starts a new fragment, shaped on its own, at every change of Unicode script, and
        # counts a combining accent (script "Inherited") as a change: the accent then loses its
        # letter. Certificate text is Latin and common punctuation: shape each line whole.
        if self.text_shaping and not markdown:
            yield Fragment(text, self._get_current_graphics_state(), self.k)
            return
        yield from super()._parse_chars(text, markdown, _initial_emphasis=_initial_emphasis)

    def _shaping(self, text: str) -> bool:
        # HarfBuzz places combining accents over their letters, at about twice the cost of a plain
        # line: only text that has them is shaped.
        wanted = fonts.needs_shaping(text)
        if wanted != bool(self.text_shaping):
            self.set_text_shaping(wanted)
        return wanted

    def both(self, say: Callable[[], str]) -> list[str]:
        """`say()` in English, then in the paper's second language unless it reads the same (NFC)."""
        with use_locale(ENGLISH):
            english = say()
        if self.second_language is None:
            return [english]
        with use_locale(self.second_language):
            other = unicodedata.normalize("NFC", say())
        return [english] if other == english else [english, other]

    def measure_words(self, width: float, say: Callable[[], str], size: float, bold: bool = False) -> float:
        """The height (mm) of `say()` in the paper's languages (see `words`)."""
        texts = self.both(say)
        height = self.measure(width, texts[0], size, bold)
        return height + sum(self.measure(width, text, second_size(size), bold) for text in texts[1:])

    def words(
        self,
        x: float,
        y: float,
        width: float,
        say: Callable[[], str],
        size: float,
        bold: bool = False,
        align: str = "L",
    ) -> float:
        """Draw `say()` in English and, under it a little smaller, in the second language; the y below."""
        texts = self.both(say)
        y = self.box(x, y, width, texts[0], size, bold=bold, align=align)
        if len(texts) == 1:
            return y
        colour = self.text_color
        if colour == BLACK:  # on white the translation is a dark grey, on a coloured band as it is
            self.set_text_color(*SECOND_RGB)
        for text in texts[1:]:
            y = self.box(x, y, width, text, second_size(size), bold=bold, align=align)
        self.text_color = colour
        return y

    def room(self, height: float) -> None:
        """Start a new page unless `height` mm fit below the cursor."""
        if self.get_y() + height > BOTTOM:
            self.new_page()

    def new_page(self) -> None:
        """A new page that names the document it continues."""
        self.add_page()
        self.set_xy(MARGIN, MARGIN)
        y = self.box(MARGIN, MARGIN, CONTENT_W, self.continued, 11, bold=True)
        self.set_xy(MARGIN, y + 3)

    def draw_raw(self, operators: str) -> None:
        """Append PDF content operators to the current page as they are."""
        self._out(operators)

    def region(self, kind: str, x: float, y: float, w: float, h: float) -> None:
        """Record a graphic's region on the current page."""
        self.layout.regions.append(Region(kind, self.page, x, y, w, h))

    def page_lines(self, left: str) -> None:
        """At the foot of every page: `left`, and 'Page i of n' on the right (and in the second language)."""
        pages = self.page
        for page in range(1, pages + 1):
            self.page = page
            y = PAGE_H - FOOT - line_height(7.5)
            self.box(MARGIN, y, CONTENT_W / 2, left, 7.5)
            count = {"page": page, "pages": pages}
            numbered = " / ".join(self.both(lambda count=count: _("Page %(page)s of %(pages)s") % count))  # type: ignore[misc]
            self.box(MARGIN + CONTENT_W / 2, y, CONTENT_W / 2, numbered, 7.5, align="R")
        self.page = pages


def _wrap(text: str, width: float, wide: Callable[[str], float]) -> list[str]:
    """Greedy line breaking at spaces; a word wider than the line is cut between letters."""
    lines: list[str] = []
    line = ""
    for word in text.split(" "):
        candidate = f"{line} {word}" if line else word
        if wide(candidate) <= width:
            line = candidate
            continue
        if line:
            lines.append(line)
        line = word
        while wide(line) > width:
            cut = _fits(line, width, wide)
            lines.append(line[:cut])
            line = line[cut:]
    lines.append(line)
    return lines


def _fits(word: str, width: float, wide: Callable[[str], float]) -> int:
    """How many characters of `word` fit in `width`, never parting a letter from its accents."""
    cut = 1
    for end in range(1, len(word) + 1):
        if wide(word[:end]) > width:
            break
        if end == len(word) or not unicodedata.combining(word[end]):
            cut = end
    return max(cut, 1)
