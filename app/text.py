"""The one rule for text a person gives the service, at every door (API, pages, CLI).

Makes, models, names, emails, reasons and identifiers are refused when they hold a character that
cannot be seen, shown or stored faithfully, so that two texts that look alike are the same text:
- control characters (Cc: C0, DEL, C1; NUL is one, and PostgreSQL cannot store it);
- format characters (Cf): text-direction controls (a right-to-left override makes `Bajaj` read as
  `jajaB`), zero-width characters, the soft hyphen U+00AD, invisible operators U+2061-2064, the
  deprecated format controls U+206A-206F, interlinear annotation U+FFF9-FFFB, the Mongolian vowel
  separator U+180E, and the tag characters U+E0000-E007F (which can hide a whole text in a name);
- the line and paragraph separators U+2028 and U+2029 (Zl, Zp): a text area's line breaks are the
  only breaks a reason may hold;
- private-use characters (Co): they mean whatever a font says, so nobody can tell what was stored;
- invisible fillers that Unicode files as letters or symbols: the Hangul fillers U+115F, U+1160,
  U+3164 and U+FFA0, the Braille blank U+2800 (a blank cell looks like a space and is not one), the
  combining grapheme joiner U+034F, the Khmer inherent vowels U+17B4 and U+17B5, and the variation
  selectors (U+180B-180D, U+180F, U+FE00-FE0F, U+E0100-E01EF), which change nothing a reader sees
  in a make, a name or a plate;
- unpaired surrogates (not characters at all; they cannot be written as UTF-8) and the replacement
  character U+FFFD (what a form or URL that was not valid UTF-8 is decoded to: the text sent was lost).
Each refusal names the character by code point and name ("U+00AD (SOFT HYPHEN)"). Unassigned code
points are accepted: a phone may know a newer Unicode than the server. Spaces other than U+0020
(such as U+00A0) are accepted as typed.

Accepted text is normalised to NFC, so a name typed with combining accents (`S` + U+0323, `a` +
U+0300) is stored in its composed form, and text longer than its limit is refused, never cut.

The rule is pure (no HTTP, no database): each door turns a `TextProblem` into its own refusal.
`REFUSED_RANGES` is the whole set, from which app.api.fields writes the schema's `pattern`.
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass

from app.errors import InvalidInput

# Rule names, as the API reports them in `errors[].rule`.
CONTROL = "control_character"
BIDI = "bidi_control"
INVISIBLE = "invisible_character"
SURROGATE = "unpaired_surrogate"
REPLACEMENT = "replacement_character"
FORMAT = "format_character"
TAG = "tag_character"
SEPARATOR = "separator_character"
PRIVATE_USE = "private_use_character"
TOO_LONG = "max_length"
REQUIRED = "required"

# Text-direction embeddings, overrides and isolates, and the direction marks.
BIDI_CONTROLS = frozenset(
    [*map(chr, range(0x202A, 0x202F)), *map(chr, range(0x2066, 0x206A)), "\u200e", "\u200f", "\u061c"]
)
# Zero-width space, non-joiner, joiner, word joiner and the byte-order mark (zero-width no-break space).
ZERO_WIDTH = frozenset(["\u200b", "\u200c", "\u200d", "\u2060", "\ufeff"])
LINE_BREAKS = frozenset("\t\n\r")
# Invisible characters Unicode does not file as format characters (see the module's docstring).
FILLERS = (
    (0x034F, 0x034F),
    (0x115F, 0x1160),
    (0x17B4, 0x17B5),
    (0x180B, 0x180D),
    (0x180F, 0x180F),
    (0x2800, 0x2800),
    (0x3164, 0x3164),
    (0xFE00, 0xFE0F),
    (0xFFA0, 0xFFA0),
    (0xE0100, 0xE01EF),
)
# Every code point of categories Cc, Cf, Zl, Zp, Co and Cs (Unicode 14.0, Python 3.11's; written out
# because computing it takes a second at start-up; tests/unit/test_text_ranges.py checks it).
CATEGORY_RANGES = (
    (0x0000, 0x001F),
    (0x007F, 0x009F),
    (0x00AD, 0x00AD),
    (0x0600, 0x0605),
    (0x061C, 0x061C),
    (0x06DD, 0x06DD),
    (0x070F, 0x070F),
    (0x0890, 0x0891),
    (0x08E2, 0x08E2),
    (0x180E, 0x180E),
    (0x200B, 0x200F),
    (0x2028, 0x202E),
    (0x2060, 0x2064),
    (0x2066, 0x206F),
    (0xD800, 0xF8FF),
    (0xFEFF, 0xFEFF),
    (0xFFF9, 0xFFFB),
    (0x110BD, 0x110BD),
    (0x110CD, 0x110CD),
    (0x13430, 0x13438),
    (0x1BCA0, 0x1BCA3),
    (0x1D173, 0x1D17A),
    (0xE0001, 0xE0001),
    (0xE0020, 0xE007F),
    (0xF0000, 0xFFFFD),
    (0x100000, 0x10FFFD),
)
REFUSED_CATEGORIES = frozenset({"Cc", "Cf", "Zl", "Zp", "Co", "Cs"})
# Every refused code point, in order, as (first, last) ranges: the categories, the fillers, U+FFFD.
REFUSED_RANGES = tuple(sorted((*CATEGORY_RANGES, *FILLERS, (0xFFFD, 0xFFFD))))
_NAMES = {
    0: "NUL",
    0x7F: "DELETE",
    0x85: "NEXT LINE",
    0x09: "TAB",
    0x0A: "LINE FEED",
    0x0D: "CARRIAGE RETURN",
}


def _character_class(ranges: tuple[tuple[int, int], ...], *, leave: str = "") -> re.Pattern[str]:
    """A regular expression matching one character of `ranges`, except those in `leave`."""
    parts = []
    for first, last in ranges:
        for low, high in _without(first, last, {ord(c) for c in leave}):
            parts.append(re.escape(chr(low)) + ("" if low == high else "-" + re.escape(chr(high))))
    return re.compile("[" + "".join(parts) + "]")


def _without(first: int, last: int, gaps: set[int]) -> list[tuple[int, int]]:
    """The range first..last with the code points of `gaps` taken out."""
    pieces, start = [], first
    for gap in sorted(g for g in gaps if first <= g <= last):
        if start < gap:
            pieces.append((start, gap - 1))
        start = gap + 1
    if start <= last:
        pieces.append((start, last))
    return pieces


_REFUSED = _character_class(REFUSED_RANGES)
_REFUSED_MULTILINE = _character_class(REFUSED_RANGES, leave="\t\n\r")


@dataclass(frozen=True)
class TextProblem:
    """Why a text is refused: the rule, and what to do in words (no field name, lower case)."""

    rule: str
    message: str


class TextRefused(ValueError):
    """A text breaks the rule; `problem` says which part and what to do."""

    def __init__(self, problem: TextProblem) -> None:
        super().__init__(problem.message)
        self.problem = problem


def describe(char: str) -> str:
    """`U+202E (RIGHT-TO-LEFT OVERRIDE)`: a character by its code point and, where it has one, its name."""
    code = ord(char)
    name = _NAMES.get(code) or unicodedata.name(char, "")
    if not name and unicodedata.category(char) == "Co":
        name = "PRIVATE USE"
    return f"U+{code:04X} ({name})" if name else f"U+{code:04X}"


def _kind(char: str, *, multiline: bool) -> str | None:
    """The rule a single character breaks, or None."""
    code = ord(char)
    if code < 0x20 or 0x7F <= code <= 0x9F:
        return None if multiline and char in LINE_BREAKS else CONTROL
    if char in BIDI_CONTROLS:
        return BIDI
    if char in ZERO_WIDTH:
        return INVISIBLE
    if 0xD800 <= code <= 0xDFFF:
        return SURROGATE
    if char == "\ufffd":
        return REPLACEMENT
    if 0xE0000 <= code <= 0xE007F:
        return TAG
    category = unicodedata.category(char)
    if category == "Cf":
        return FORMAT
    if category in ("Zl", "Zp"):
        return SEPARATOR
    if category == "Co":
        return PRIVATE_USE
    if any(first <= code <= last for first, last in FILLERS):
        return INVISIBLE
    return None


_WHY = {
    CONTROL: "text may not hold control characters",
    BIDI: "it changes the direction the text is shown in, so it would not read as it is stored",
    INVISIBLE: "it cannot be seen, so two texts that look the same would differ",
    SURROGATE: "it is half of a UTF-16 pair, not a character; send the text as valid UTF-8",
    REPLACEMENT: "it stands for bytes that were not valid UTF-8; send the text again as UTF-8",
    FORMAT: "it is a format character that cannot be seen, so two texts that look the same would differ",
    TAG: "tag characters cannot be seen, so the text would hold more than it shows",
    SEPARATOR: "it breaks the line where no line break is allowed",
    PRIVATE_USE: "a private-use character means whatever a font makes of it, so nobody can tell what it is",
}
_WHAT = {
    CONTROL: "the control character",
    BIDI: "the text-direction control",
    INVISIBLE: "the invisible character",
    SURROGATE: "the unpaired surrogate",
    REPLACEMENT: "the replacement character",
    FORMAT: "the format character",
    TAG: "the tag character",
    SEPARATOR: "the separator",
    PRIVATE_USE: "the private-use character",
}


def character_problem(value: str, *, multiline: bool = False) -> TextProblem | None:
    """The first refused character of `value`, in words, or None when every character is allowed."""
    found = (_REFUSED_MULTILINE if multiline else _REFUSED).search(value)
    if found is None:
        return None
    char, position = found.group(), found.start() + 1
    rule = _kind(char, multiline=multiline) or INVISIBLE
    message = f"remove {_WHAT[rule]} {describe(char)} at character {position}; {_WHY[rule]}"
    return TextProblem(rule, message)


def without_refused(value: str, *, multiline: bool = False) -> str:
    """`value` with every refused character taken out (to show a refused form again, safely)."""
    return (_REFUSED_MULTILINE if multiline else _REFUSED).sub("", value)


def check_text(
    value: str, *, max_length: int, required: bool = True, multiline: bool = False, strip: bool = True
) -> str:
    """The text as stored: refused characters raise TextRefused; then NFC, stripped, length-checked.

    `required` refuses a blank text; otherwise a blank one comes back as "". `multiline` lets tabs
    and line breaks through (a reason typed in a text area); `strip=False` keeps the edges (passwords).
    """
    problem = character_problem(value, multiline=multiline)
    if problem is not None:
        raise TextRefused(problem)
    text = unicodedata.normalize("NFC", value)
    if strip:
        text = text.strip()
    if required and not text:
        raise TextRefused(TextProblem(REQUIRED, "enter some text, not only spaces"))
    # The limit holds for the text as sent (what the API schema states) and as stored.
    longest = max(len(value), len(text))
    if longest > max_length:
        raise TextRefused(TextProblem(TOO_LONG, f"give at most {max_length} characters, not {longest}"))
    return text


def checked(
    field: str,
    value: str,
    *,
    max_length: int,
    required: bool = True,
    multiline: bool = False,
    strip: bool = True,
) -> str:
    """`check_text` for a service: a refusal is an InvalidInput (422) naming the field and the rule."""
    try:
        return check_text(value, max_length=max_length, required=required, multiline=multiline, strip=strip)
    except TextRefused as refused:
        problem = refused.problem
        raise InvalidInput(f"{field}: {problem.message}", field=field, rule=problem.rule) from refused


def optional_checked(field: str, value: str | None, *, max_length: int) -> str | None:
    """`checked` for text that may be left out: None or blank comes back as None."""
    if value is None:
        return None
    return checked(field, value, max_length=max_length, required=False) or None
