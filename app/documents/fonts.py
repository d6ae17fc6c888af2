"""The certificate's typeface: Noto Sans from PyPI (fontpkg-noto-sans), embedded as a Unicode TrueType font.

The package ships the variable font. Once per process, HarfBuzz's subsetter pins it to a regular and
a bold instance and keeps only the repertoire a certificate needs (Latin with the letters of Yoruba,
Hausa, Igbo and other Nigerian languages, combining accents, punctuation, the naira): some 20 ms,
where fontTools' instancer takes seconds. Each PDF then gets a copy of the parsed font that shares
the widths and the character map and only re-reads the small font to embed its subset.
"""

from __future__ import annotations

import io
import logging
import unicodedata
from dataclasses import dataclass
from functools import cache, lru_cache
from pathlib import Path
from typing import Any

import fontpkg_noto_sans
import uharfbuzz as hb
from fontTools import subset as ftsubset
from fontTools import ttLib
from fpdf import FPDF
from fpdf import output as fpdf_output
from fpdf.fonts import HarfBuzzFont, SubsetMap, TTFFont

FAMILY = "noto"
REPLACEMENT = "\ufffd"  # drawn for a character the font lacks: visible, never a silent '?'
_LOG = logging.getLogger("trikecert.certificates.pdf")
_REPERTOIRE = (
    (0x20, 0x7E),  # Basic Latin
    (0xA0, 0x24F),  # Latin-1, Latin Extended-A and -B (Ɓ ɓ Ɗ ɗ Ƙ ƙ Ŋ ŋ)
    (0x250, 0x2FF),  # IPA letters used in African orthographies (ɛ ɔ), spacing modifiers
    (0x300, 0x36F),  # combining diacritics (Yoruba tones over dotted letters)
    (0x1E00, 0x1EFF),  # Latin Extended Additional (ẹ ọ ṣ with their tones)
    (0x2000, 0x206F),  # general punctuation
    (0x20A0, 0x20C0),  # currency signs (₦)
    (0x2100, 0x2122),  # letterlike symbols (™, №)
    (0x2190, 0x2199),  # arrows
    (0x2212, 0x2212),  # minus sign
    (0x25CC, 0x25CC),  # dotted circle (a lone combining mark)
    (0xFFFD, 0xFFFD),  # the replacement character itself
)
_STYLES = {"": 400, "B": 700}


@dataclass(frozen=True)
class _Face:
    """One prepared style: the font to embed (no layout tables), and with them for HarfBuzz."""

    embed: bytes
    shaping: bytes


def font_file() -> Path:
    """The variable Noto Sans file installed with the fontpkg-noto-sans package."""
    return Path(fontpkg_noto_sans.ROOT) / "files" / "NotoSans[wdth,wght].ttf"


@lru_cache(maxsize=1)
def _faces() -> dict[str, _Face]:
    face = hb.Face(hb.Blob.from_file_path(str(font_file())))
    faces = {}
    for style, weight in _STYLES.items():
        wanted = hb.SubsetInput()
        for low, high in _REPERTOIRE:
            wanted.unicode_set.update(range(low, high + 1))
        wanted.pin_axis_location(face, "wght", weight)
        wanted.pin_axis_location(face, "wdth", 100)
        wanted.flags = hb.SubsetFlags.NO_HINTING | hb.SubsetFlags.NOTDEF_OUTLINE | hb.SubsetFlags.GLYPH_NAMES
        shaping = hb.subset(face, wanted)
        if shaping is None:  # pragma: no cover - only if the package shipped a broken font
            raise RuntimeError(f"could not prepare {font_file()}")
        font = ttLib.TTFont(io.BytesIO(shaping.blob.data))
        # fpdf2 drops these from the embedded subset anyway; without them each render parses far less.
        for tag in ("GSUB", "GPOS", "GDEF", "STAT", "gasp"):
            if tag in font:
                del font[tag]
        embed = io.BytesIO()
        font.save(embed)
        faces[style] = _Face(embed=embed.getvalue(), shaping=bytes(shaping.blob.data))
    return faces


@cache
def _prototype(style: str) -> TTFFont:
    face = _faces()[style]
    # TTFFont reads its font through fontTools, which takes a file object as well as a path.
    proto = TTFFont(FPDF(), io.BytesIO(face.embed), f"{FAMILY}{style}", style)  # type: ignore[arg-type]
    # Documents render in several threads and share this parsed font: read it whole now, so that no
    # lazy read from its file object happens later, concurrently.
    proto.ttfont.ensureDecompiled()
    return proto


@lru_cache(maxsize=len(_STYLES))
def _shaping_face(style: str) -> hb.Face:
    return hb.Face(hb.Blob(_faces()[style].shaping))


def _copy_for(pdf: FPDF, style: str) -> TTFFont:
    """A font for one document: shared widths, cmap, shaper and parsed font; its own subset map."""
    proto = _prototype(style)
    font = TTFFont.__new__(TTFFont)
    for slot in TTFFont.__slots__:
        if hasattr(proto, slot):
            setattr(font, slot, getattr(proto, slot))
    font.i = len(pdf.fonts) + 1
    font._hbfont = HarfBuzzFont(_shaping_face(style))  # its own: shaping sets the font's size
    font.missing_glyphs = []
    font.subset = SubsetMap(font)
    return font


@lru_cache(maxsize=len(_STYLES))
def _embed_face(style: str) -> hb.Face:
    return hb.Face(hb.Blob(_faces()[style].embed))


def cut(font: TTFFont) -> None:
    """Give `font` its own small font of just the glyphs the document used, for fpdf2 to embed.

    fpdf2 subsets the font it embeds in place with fontTools, whose cost grows with the glyphs
    in the font: HarfBuzz cuts the document's few dozen first (well under a millisecond), keeping
    the glyph names by which fpdf2 finds them again. The shared parsed font is never altered.
    """
    used = {glyph.glyph_id for glyph, _code in font.subset.items() if glyph is not None}
    wanted = hb.SubsetInput()
    wanted.glyph_set.update(used | {0})
    wanted.flags = (
        hb.SubsetFlags.GLYPH_NAMES | hb.SubsetFlags.NOTDEF_OUTLINE | hb.SubsetFlags.NO_LAYOUT_CLOSURE
    )
    small = hb.subset(_embed_face(font.fontkey.removeprefix(FAMILY)), wanted)
    font.ttfont = _Cut(small.blob.data)


class _Cut(ttLib.TTFont):  # type: ignore[misc]
    """A font already cut to the document's glyphs: fontTools need neither cut it again nor rebuild it."""

    def __init__(self, data: bytes) -> None:
        super().__init__(io.BytesIO(data), recalcTimestamp=False, recalcBBoxes=False, lazy=True)
        self.data = data

    def save(self, file: Any, reorderTables: bool | None = True) -> None:  # noqa: N803 (fontTools' name)
        """Write the font as HarfBuzz made it: nothing has changed it since."""
        file.write(self.data)


class _Subsetter(ftsubset.Subsetter):  # type: ignore[misc]
    """fpdf2's subsetter, which leaves a font that `cut` made as it is."""

    def subset(self, font: ttLib.TTFont) -> None:
        """Subset `font` in place, unless `cut` already did (a third of a render's time)."""
        if not isinstance(font, _Cut):
            super().subset(font)


class _SubsetModule:
    """What fpdf2's output module uses of fontTools.subset, with the subsetter above."""

    Options = ftsubset.Options
    Subsetter = _Subsetter


fpdf_output.ftsubset = _SubsetModule  # type: ignore[attr-defined]  # fpdf2 looks the subsetter up here when it writes the fonts


def widths(style: str) -> dict[int, float]:
    """Advance widths per code point, in thousandths of the font size."""
    return _prototype(style).cw


def install(pdf: FPDF) -> list[TTFFont]:
    """Make the family `noto` (regular and bold) available to `pdf.set_font`; `cut` them before output."""
    installed = []
    for style in _STYLES:
        font = _copy_for(pdf, style)
        pdf.fonts[font.fontkey] = font
        installed.append(font)
    return installed


def warm() -> None:
    """Prepare the fonts now (about 20 ms), so the first certificate does not pay for it."""
    for style in _STYLES:
        _prototype(style)


@lru_cache(maxsize=1)
def _covered() -> frozenset[int]:
    return frozenset(_prototype("").cmap) & frozenset(_prototype("B").cmap)


class Printable:
    """Maps text to what the font can draw; characters it lacks become U+FFFD, each logged once."""

    def __init__(self) -> None:
        self.missing: set[str] = set()

    def __call__(self, text: str) -> str:
        """The text with every character the font lacks replaced by U+FFFD."""
        covered = _covered()
        if all(ord(char) in covered for char in text):
            return text
        out = []
        for char in text:
            if ord(char) in covered:
                out.append(char)
                continue
            if char not in self.missing:
                self.missing.add(char)
            out.append(REPLACEMENT)
        return "".join(out)

    def report(self, number: str) -> None:
        """Log, once per document, which characters were drawn as U+FFFD."""
        if self.missing:
            names = ", ".join(f"U+{ord(c):04X} {unicodedata.name(c, '?')}" for c in sorted(self.missing))
            _LOG.warning("certificate %s: the font lacks %s; drawn as U+FFFD", number, names)


def needs_shaping(text: str) -> bool:
    """True when the text holds a combining mark, which only a shaper places well over its letter."""
    return any(unicodedata.combining(char) for char in text)
