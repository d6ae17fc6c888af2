"""Field types of the API whose validation is exactly what their OpenAPI schema states.

Pydantic's datetime is lenient (it takes `0.5` as a Unix time, a space for the `T`, a missing time
zone) and strict where RFC 3339 is not (leap seconds, year 0). `Timestamp` accepts exactly the JSON
Schema `date-time` format and nothing else, so the schema is the contract.

`text()` is free text (makes, models, labels) and `identifier()` a code with a fixed shape
(registrations): both keep to app.text's rule for every door (no control, text-direction or
invisible characters, no unpaired surrogates, NFC, refused when too long) and refuse in words, never
by printing a regular expression. Their schema states the same as a `pattern` and `maxLength`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Annotated, Any

from pydantic import BeforeValidator, GetCoreSchemaHandler, GetJsonSchemaHandler, WithJsonSchema
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import CoreSchema, PydanticCustomError, core_schema

from app.text import REFUSED_RANGES, REQUIRED, TextRefused, check_text

# The characters app.text refuses, and those Python's str.strip() removes, spelt out so that the
# pattern means the same to Python and to ECMA 262 with the `u` flag (ajv's default; JSON Schema's
# patterns are code points): the Basic Multilingual Plane's as `\uXXXX` escapes, those beyond it
# (tags, private use) as the characters themselves (JSON writes them as a surrogate pair, which a `u`
# pattern reads as one code point). Unpaired surrogates are refused too, but no pattern can say so:
# Rust's and other engines refuse a surrogate in a pattern.
SURROGATES = (0xD800, 0xDFFF)


def _escaped(code: int) -> str:
    if code < 0x10000:
        return f"\\u{code:04x}" if code > 0xFF else f"\\x{code:02x}"
    return chr(code)


def _class(ranges: tuple[tuple[int, int], ...]) -> str:
    """The inside of a character class holding every code point of `ranges` but the surrogates."""
    parts = []
    for first, last in ranges:
        pieces = [(first, min(last, SURROGATES[0] - 1)), (max(first, SURROGATES[1] + 1), last)]
        for low, high in pieces:
            if low <= high:
                parts.append(_escaped(low) + ("" if low == high else "-" + _escaped(high)))
    return "".join(parts)


_REFUSED = _class(REFUSED_RANGES)
_BLANK_OR_REFUSED = _REFUSED + r"\x20\xa0\u1680\u2000-\u200a\u202f\u205f\u3000"
TEXT_PATTERN = rf"^[^{_REFUSED}]*[^{_BLANK_OR_REFUSED}][^{_REFUSED}]*$"


@dataclass(frozen=True)
class TextRule:
    """Pydantic metadata: the text rule of app.text on a `str`, with its JSON schema."""

    max_length: int
    description: str | None = None
    min_length: int = 1
    shape: re.Pattern[str] | None = None  # an identifier's shape, checked after the text rule
    shape_words: str = ""  # what the shape is, in words, for the refusal

    def validate(self, value: str) -> str:
        """The text as stored, or a PydanticCustomError whose type is the rule broken."""
        try:
            text = check_text(value, max_length=self.max_length)
        except TextRefused as refused:
            problem = refused.problem
            message = "must not be blank" if problem.rule == REQUIRED else problem.message
            raise PydanticCustomError(problem.rule, message) from refused
        if self.shape is not None and not self.shape.fullmatch(text):
            raise PydanticCustomError("format", self.shape_words)
        return text

    def __get_pydantic_core_schema__(self, source: Any, handler: GetCoreSchemaHandler) -> CoreSchema:
        """A str, then the rule."""
        return core_schema.no_info_after_validator_function(self.validate, handler(source))

    def __get_pydantic_json_schema__(
        self, schema: CoreSchema, handler: GetJsonSchemaHandler
    ) -> JsonSchemaValue:
        """The string's schema with the rule's bounds and pattern."""
        json_schema = handler(schema)
        json_schema.update(minLength=self.min_length, maxLength=self.max_length)
        json_schema["pattern"] = self.shape.pattern if self.shape is not None else TEXT_PATTERN
        if self.description:
            json_schema["description"] = self.description
        return json_schema


def text(max_length: int, description: str | None = None) -> TextRule:
    """Free text of 1 to `max_length` characters under the text rule (use as `Annotated[str, text(80)]`)."""
    return TextRule(max_length, description)


def identifier(
    pattern: str, *, min_length: int, max_length: int, words: str, description: str | None = None
) -> TextRule:
    """An identifier of the shape `pattern` under the text rule; `words` says the shape when refused."""
    return TextRule(max_length, description, min_length, re.compile(pattern), words)


_RFC3339 = re.compile(
    r"(?P<year>\d{4})-(?P<month>\d{2})-(?P<day>\d{2})[Tt]"
    r"(?P<hour>\d{2}):(?P<minute>\d{2}):(?P<second>\d{2})(?:\.(?P<fraction>\d+))?"
    r"(?:(?P<utc>[Zz])|(?P<sign>[+-])(?P<offset_hour>\d{2}):(?P<offset_minute>\d{2}))",
    re.ASCII,
)
_EARLIEST = datetime.min.replace(tzinfo=UTC)
_LATEST = datetime.max.replace(tzinfo=UTC)


def _days_in_month(year: int, month: int) -> int:
    if month == 2:
        leap = year % 4 == 0 and (year % 100 != 0 or year % 400 == 0)
        return 29 if leap else 28
    return 30 if month in (4, 6, 9, 11) else 31


def parse_timestamp(text: str) -> datetime:
    """An RFC 3339 `date-time` as an aware UTC datetime; ValueError names what is wrong.

    Year 0 and instants past year 9999 are clamped to the earliest and latest representable
    time, and a leap second to the last microsecond before it: for a time filter that is exact.
    """
    match = _RFC3339.fullmatch(text)
    if match is None:
        raise ValueError("give an RFC 3339 date and time with a time zone, such as 2026-11-23T13:32:00Z")
    numbers = ("year", "month", "day", "hour", "minute", "second", "offset_hour", "offset_minute")
    part = {name: int(match[name]) for name in numbers if match[name]}
    year, month, day = part["year"], part["month"], part["day"]
    hour, minute, second = part["hour"], part["minute"], part["second"]
    offset = 0
    if match["sign"]:
        if part["offset_hour"] > 23 or part["offset_minute"] > 59:
            raise ValueError("the time zone offset must be between -23:59 and +23:59")
        offset = (part["offset_hour"] * 60 + part["offset_minute"]) * (1 if match["sign"] == "+" else -1)
    if not 1 <= month <= 12 or not 1 <= day <= _days_in_month(year, month):
        raise ValueError(f"{text[:10]} is not a date in the calendar")
    if hour > 23 or minute > 59 or second > 60:
        raise ValueError(f"{text[11:19]} is not a time of day")
    leap = second == 60
    if leap and (hour * 60 + minute - offset) % (24 * 60) != 23 * 60 + 59:
        raise ValueError("a leap second (:60) can only fall at 23:59:60 UTC")
    micro = 999_999 if leap else int(((match["fraction"] or "") + "000000")[:6])
    if year == 0:
        return _EARLIEST
    local = datetime(year, month, day, hour, minute, 59 if leap else second, micro)
    try:
        return (local - timedelta(minutes=offset)).replace(tzinfo=UTC)
    except OverflowError:  # within a day of year 1 or year 9999 and pushed past it by the offset
        return _EARLIEST if offset > 0 else _LATEST


def _timestamp(value: Any) -> Any:
    if isinstance(value, datetime):
        return value
    if not isinstance(value, str):
        raise PydanticCustomError("datetime_format", "give an RFC 3339 date and time as a string")
    try:
        return parse_timestamp(value)
    except ValueError as error:
        raise PydanticCustomError("datetime_format", str(error)) from error


Timestamp = Annotated[
    datetime,
    BeforeValidator(_timestamp),
    WithJsonSchema({"type": "string", "format": "date-time"}),
]
