"""The text rule's written-out ranges are exactly the Unicode categories it names, and the rule and
the API schema's pattern refuse the same characters (every code point checked once)."""

from __future__ import annotations

import re
import unicodedata

import jsonschema_rs

from app.api.fields import TEXT_PATTERN
from app.text import (
    CATEGORY_RANGES,
    REFUSED_CATEGORIES,
    REFUSED_RANGES,
    character_problem,
    check_text,
)


def _ranges(codes: list[int]) -> list[tuple[int, int]]:
    found: list[tuple[int, int]] = []
    for code in codes:
        if found and found[-1][1] == code - 1:
            found[-1] = (found[-1][0], code)
        else:
            found.append((code, code))
    return found


def test_the_written_out_ranges_are_the_refused_categories_of_this_python_s_unicode() -> None:
    codes = [c for c in range(0x110000) if unicodedata.category(chr(c)) in REFUSED_CATEGORIES]
    assert list(CATEGORY_RANGES) == _ranges(codes), f"Unicode {unicodedata.unidata_version}: write them again"


def test_the_schema_pattern_is_a_regular_expression_to_json_schema_validators() -> None:
    validator = jsonschema_rs.validator_for({"type": "string", "pattern": TEXT_PATTERN})
    assert validator.is_valid("Ṣàngó 😀")
    for refused in ("Baj\u00adaj", "a\U000e0041", "\ue000", "\u3164", "\x9aBajaj", " "):
        assert not validator.is_valid(refused), f"{refused!r}"


def test_the_rule_and_the_schema_pattern_refuse_exactly_the_refused_ranges() -> None:
    refused = {c for first, last in REFUSED_RANGES for c in range(first, last + 1)}
    pattern = re.compile(TEXT_PATTERN)
    for code in range(0x110000):
        text = f"a{chr(code)}b"
        by_rule = character_problem(text) is not None
        assert by_rule == (code in refused), f"U+{code:04X}"
        if not 0xD800 <= code <= 0xDFFF:  # no pattern can name a surrogate (see app/api/fields.py)
            assert (pattern.search(text) is None) == by_rule, f"U+{code:04X}: the pattern disagrees"


def test_a_text_area_takes_its_own_line_breaks_but_no_unicode_separator() -> None:
    assert check_text("one\r\ntwo\tthree", max_length=50, multiline=True) == "one\r\ntwo\tthree"
    for char in ("\u2028", "\u2029", "\u00ad", "\U000e0041"):
        problem = character_problem(f"one{char}two", multiline=True)
        assert problem is not None, f"U+{ord(char):04X}"
        assert f"U+{ord(char):04X} (" in problem.message
