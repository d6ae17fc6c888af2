"""A tone mark over a dotted letter (Yoruba's ọ̀, ẹ̀) is drawn where a reader sees it, at screen and print
resolutions: the grave above the letter, not lost or moved below the line with the dot.

The mark's place is read from the PDF itself (the position fpdf2 gives the shaped glyph) and its ink
box from the font's own outline, so the test checks what a rasteriser (poppler) draws there.
"""

from __future__ import annotations

import io
import re
import shutil
import subprocess
import unicodedata
from typing import Any

import pytest
import uharfbuzz as hb
from needed_tools import tool_missing
from PIL import Image
from pypdf import PdfReader

from app.documents import fonts
from app.documents.layout import Page

GRAVE = "\u0300"


def _grave_extents() -> hb.GlyphExtents:
    """The combining grave's ink box, in font units, relative to its own origin."""
    font = hb.Font(fonts._shaping_face(""))
    return font.get_glyph_extents(font.get_nominal_glyph(ord(GRAVE)))


def _grave_codes(pdf: PdfReader) -> set[int]:
    """The codes the document draws the combining grave with (from its ToUnicode map)."""
    resources: Any = pdf.pages[0]["/Resources"]
    cmap = resources["/Font"]["/F1"]["/ToUnicode"].get_data().decode()
    return {
        int(code, 16) for code, char in re.findall(r"<([0-9A-F]{4})> <([0-9A-F]{4})>", cmap) if char == "0300"
    }


@pytest.mark.parametrize("dpi", [100, 150, 300])
@pytest.mark.parametrize("text", ["wọ̀", "òdiwọ̀n Ìyàtọ̀ ẹ̀gbẹ́"])
def test_a_grave_over_a_dotted_letter_has_ink_above_the_letter(text: str, dpi: int) -> None:
    if shutil.which("pdftoppm") is None:
        tool_missing("pdftoppm", "apt-get install poppler-utils")
    page = Page(continued="")
    page.add_page()
    page.box(20, 20, 150, text, 9)
    document = bytes(page.output())
    reader = PdfReader(io.BytesIO(document))
    contents = reader.pages[0].get_contents()
    assert contents is not None
    stream = contents.get_data()
    height = float(reader.pages[0].mediabox.height)
    codes = _grave_codes(reader)
    extents = _grave_extents()
    png = subprocess.run(
        ["pdftoppm", "-r", str(dpi), "-png", "-"], input=document, capture_output=True, check=True
    ).stdout
    image = Image.open(io.BytesIO(png)).convert("L")
    scale = dpi / 72
    size = 9 / 1000  # points per font unit
    # fpdf2 draws each shaped mark at its own text matrix: "1 0 0 1 x y Tm (<code>) Tj".
    marks = [
        (float(x), float(y))
        for x, y, code in re.findall(rb"1 0 0 1 ([\d.]+) ([\d.]+) Tm \((..)\) Tj", stream, flags=re.DOTALL)
        if int.from_bytes(code, "big") in codes
    ]
    # Every grave over a dotted letter is a mark of its own (ò and Ì are single precomposed glyphs).
    assert len(marks) == unicodedata.normalize("NFC", text).count(GRAVE) > 0
    x_height = 536  # Noto Sans' x-height (font units): the box below is above it, over the letter
    assert extents.y_bearing + extents.height > x_height
    for x, baseline in marks:
        left = (x + extents.x_bearing * size) * scale
        right = (x + (extents.x_bearing + extents.width) * size) * scale
        top = (height - baseline - extents.y_bearing * size) * scale
        bottom = (height - baseline - (extents.y_bearing + extents.height) * size) * scale
        box = (int(left), int(top), int(right) + 1, int(bottom) + 1)
        ink = [value for value in image.crop(box).tobytes() if value < 160]
        assert ink, f"no ink for the grave at {box} ({dpi} dpi)"
