"""The one rule for text a person gives the service, at every door (API, pages, CLI).

Makes, models, names, emails, reasons and identifiers are refused when they hold a character that
cannot be shown or stored faithfully: control characters (C0, DEL, C1; NUL is one, and PostgreSQL
cannot store it), text-direction controls (a right-to-left override makes `Bajaj` read as `jajaB`),
zero-width characters (two names that look alike but differ), unpaired surrogates (not
characters at all; they cannot be written as UTF-8) and the replacement character U+FFFD (what a
form or URL that was not valid UTF-8 is decoded to: the text sent was lost). Accepted text is
normalised to NFC, so a name typed with combining accents (`S` + U+0323, `a` + U+0300) is stored in
its composed form, and text longer than its limit is refused, never cut.

The rule is pure (no HTTP, no database): each door turns a `TextProblem` into its own refusal.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass

from app.errors import InvalidInput

# Rule names, as the API reports them in `errors[].rule`.
CONTROL = "control_character"
BIDI = "bidi_control"
INVISIBLE = "invisible_character"
SURROGATE = "unpaired_surrogate"
REPLACEMENT = "replacement_character"
TOO_LONG = "max_length"
REQUIRED = "required"

# Text-direction embeddings, overrides and isolates, and the direction marks.
BIDI_CONTROLS = frozenset(
    [*map(chr, range(0x202A, 0x202F)), *map(chr, range(0x2066, 0x206A)), "\u200e", "\u200f", "\u061c"]
)
# Zero-width space, non-joiner, joiner, word joiner and the byte-order mark (zero-width no-break space).
ZERO_WIDTH = frozenset(["\u200b", "\u200c", "\u200d", "\u2060", "\ufeff"])
LINE_BREAKS = frozenset("\t\n\r")
_NAMES = {
    0: "NUL",
    0x7F: "DELETE",
    0x85: "NEXT LINE",
    0x09: "TAB",
    0x0A: "LINE FEED",
    0x0D: "CARRIAGE RETURN",
}


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
    return None


_WHY = {
    CONTROL: "text may not hold control characters",
    BIDI: "it changes the direction the text is shown in, so it would not read as it is stored",
    INVISIBLE: "it cannot be seen, so two texts that look the same would differ",
    SURROGATE: "it is half of a UTF-16 pair, not a character; send the text as valid UTF-8",
    REPLACEMENT: "it stands for bytes that were not valid UTF-8; send the text again as UTF-8",
}
_WHAT = {
    CONTROL: "the control character",
    BIDI: "the text-direction control",
    INVISIBLE: "the invisible character",
    SURROGATE: "the unpaired surrogate",
    REPLACEMENT: "the replacement character",
}


def character_problem(value: str, *, multiline: bool = False) -> TextProblem | None:
    """The first refused character of `value`, in words, or None when every character is allowed."""
    if value.isprintable() and "\ufffd" not in value:  # the others are all unprintable (Cc, Cf, Cs)
        return None
    for position, char in enumerate(value, start=1):
        rule = _kind(char, multiline=multiline)
        if rule is not None:
            message = f"remove {_WHAT[rule]} {describe(char)} at character {position}; {_WHY[rule]}"
            return TextProblem(rule, message)
    return None


def without_refused(value: str, *, multiline: bool = False) -> str:
    """`value` with every refused character taken out (to show a refused form again, safely)."""
    return "".join(c for c in value if _kind(c, multiline=multiline) is None)


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
