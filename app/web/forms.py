"""Form helpers shared by the pages: reading fields, parsing numbers, and errors keyed by input id."""

from __future__ import annotations

import re
from collections.abc import Iterable
from datetime import date
from decimal import Decimal, InvalidOperation

from starlette.datastructures import FormData

from app.errors import FieldProblem
from app.i18n.active import gettext as _
from app.text import TextRefused, character_problem, check_text, without_refused
from app.web.refusals import translated_refusal

# The core and services start each message with the field's path ("readings.front_kg[1]: ...").
_FIELD_PREFIX = re.compile(r"^[A-Za-z_][\w.\[\]]*: ")
# ASCII digits only: Python's \d (and Decimal) would read Arabic-Indic or fullwidth digits as numbers.
_NUMBER = re.compile(r"^[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)$")


def text(form: FormData, name: str, errors: FormErrors, *, limit: int, multiline: bool = False) -> str:
    """A text field under the text rule (app.text), stripped and in NFC ("" when absent).

    A refused text adds its message beside the field (the input's id is its name) and comes back
    without the refused characters, to show again; a text over `limit` is refused, never cut.
    """
    value = form.get(name)
    if not isinstance(value, str):
        return ""
    try:
        return check_text(value, max_length=limit, required=False, multiline=multiline)
    except TextRefused as refused:
        errors.add(name, readable(refused.problem.message))
        return without_refused(value, multiline=multiline).strip()


def secret(form: FormData, name: str, errors: FormErrors, *, limit: int) -> str:
    """A password field: the text rule's characters and limit, but as typed (never stripped or normalised)."""
    value = form.get(name)
    if not isinstance(value, str):
        return ""
    problem = character_problem(value)
    if problem is not None:
        errors.add(name, readable(problem.message))
    elif len(value) > limit:
        errors.add(
            name,
            _("Give at most %(limit)s characters, not %(count)s") % {"limit": limit, "count": len(value)},
        )
    else:
        return value
    return ""


def query_text(value: str, name: str, errors: FormErrors, *, limit: int) -> str:
    """A filter from the query string under the text rule; refused, it adds its message and is "" ."""
    try:
        return check_text(value, max_length=limit, required=False)
    except TextRefused as refused:
        errors.add(name, readable(refused.problem.message))
        return ""


def parse_decimal(value: str) -> Decimal | None:
    """A plain decimal number typed by a person (a decimal comma is accepted), or None."""
    cleaned = value.replace(" ", "")
    if cleaned.count(",") == 1 and "." not in cleaned:
        cleaned = cleaned.replace(",", ".")
    if not _NUMBER.match(cleaned):
        return None
    try:
        return Decimal(cleaned)
    except InvalidOperation:
        return None


def ascii_digits(value: str) -> bool:
    """True for a non-empty run of the digits 0-9 only (str.isdigit also takes ٣, ３ and ²)."""
    return value.isascii() and value.isdigit()


def readable(message: str) -> str:
    """A service message without its field path, starting with a capital."""
    message = _FIELD_PREFIX.sub("", message, count=1)
    return message[:1].upper() + message[1:]


class FormErrors:
    """Errors of one form in page order, keyed by the id of the input they belong to."""

    def __init__(self) -> None:
        self.messages: dict[str, str] = {}

    def add(self, input_id: str, message: str) -> None:
        """Keep the first message for an input."""
        self.messages.setdefault(input_id, message)

    def add_problems(
        self, problems: Iterable[FieldProblem], input_for: dict[str, str], fallback: str
    ) -> None:
        """Attach service problems to inputs by the longest known path prefix, in the page's language."""
        for problem in problems:
            message = translated_refusal(readable(problem.message))
            self.add(find_input(problem.field, input_for, fallback), message)

    def __bool__(self) -> bool:
        return bool(self.messages)


# Dates a filter may name: far enough out for any inspection, and near enough that a day's bounds
# in any time zone, or a period counted back from it, stay inside what `datetime` can hold.
FIRST_FILTER_DAY = date(2000, 1, 1)
LAST_FILTER_DAY = date(2099, 12, 31)


def read_date(raw: str, input_id: str, errors: FormErrors) -> date | None:
    """A date typed as year-month-day, None when blank; otherwise an error for the input."""
    if not raw:
        return None
    try:
        day = date.fromisoformat(raw)
    except ValueError:
        errors.add(
            input_id, _("Enter the date as year-month-day, like %(example)s") % {"example": "2026-11-23"}
        )
        return None
    if not FIRST_FILTER_DAY <= day <= LAST_FILTER_DAY:
        errors.add(input_id, _("Enter a date from 1 January 2000 to 31 December 2099"))
        return None
    return day


def find_input(path: str, input_for: dict[str, str], fallback: str) -> str:
    """The input id for a service field path: exact, else its nearest known parent, else `fallback`."""
    candidate = path
    while candidate:
        if candidate in input_for:
            return input_for[candidate]
        cut = max(candidate.rfind("."), candidate.rfind("["))
        candidate = candidate[:cut] if cut > 0 else ""
    return fallback
