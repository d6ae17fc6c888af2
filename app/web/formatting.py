"""How figures, dates and times are printed everywhere (pages, PDF, CLI): one function per kind of figure."""

from __future__ import annotations

import re
from datetime import UTC, date, datetime, time, timedelta
from decimal import ROUND_HALF_EVEN, Decimal
from fractions import Fraction
from functools import lru_cache
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

from babel.dates import format_date, get_month_names
from markupsafe import Markup, escape

from app.config import get_settings
from app.i18n.active import N_, current_locale, gettext
from app.i18n.locales import ENGLISH
from app.stability import DELTA, LAYOUTS, LSF_LIMIT, Layout


def fixed(value: Decimal | Fraction | float, places: int) -> str:
    """The value rounded half-even to `places` decimals."""
    if isinstance(value, Fraction):
        value = Decimal(value.numerator) / Decimal(value.denominator)
    exponent = Decimal(1).scaleb(-places)
    return str(Decimal(value).quantize(exponent, ROUND_HALF_EVEN))


def kg(value: Decimal | Fraction | float, places: int = 1) -> str:
    """A weight in kg, to 0.1 kg by default (averaged readings)."""
    return fixed(value, places)


LOAD_PLACES = 2  # the API gives loading-case weights to 0.01 kg; every page and the PDF print the same


def load_kg(value: Decimal | Fraction | float) -> str:
    """A loading case's total or rear weight, to 0.01 kg as the API gives it: 283.49."""
    return fixed(value, LOAD_PLACES)


def ratio(value: Decimal | Fraction | float) -> str:
    """A ratio such as the LSF, to 3 decimals."""
    return fixed(value, 3)


def spread_ratio(value: Decimal | Fraction | float) -> str:
    """A type assessment's LSF statistic (min, mean, max, s, bound), to 5 decimals: 0.70375."""
    return fixed(value, 5)


def signed(value: Decimal | Fraction | float) -> str:
    """A variance with its sign, to 3 decimals: +0.009, -0.030."""
    text = fixed(value, 3)
    return text if text.startswith("-") else f"+{text}"


NOT_RECORDED = N_("Not recorded")  # English on a document's frozen facts; translated on a page


def not_recorded() -> str:
    """'Not recorded', in the active language: how every page words a gap."""
    return gettext(NOT_RECORDED)


def or_not_recorded(value: object) -> object:
    """A recorded value as it is, or 'Not recorded' (in the page's language) for one left empty."""
    return not_recorded() if value is None or value == "" else value


def unbroken(text: str) -> str:
    """A message for a page, each percentage kept on one line with its figure: '10.5\u00a0%'."""
    return text.replace(" %", "\u00a0%")


_PLATE_VALUE = re.compile(r'"registration(?:_number)?":\s*"([^"\\]+)"')


def plates_kept(details: str) -> Markup:
    """An audit event's details as text, each registration held on one line (never 'LAG 888 / YB')."""
    plates = {match.group(1) for match in _PLATE_VALUE.finditer(details)}
    shown = escape(details)
    for plate in sorted(plates, key=len, reverse=True):
        shown = shown.replace(escape(plate), Markup('<span class="plate">{}</span>').format(plate))
    return shown


def limit_text(layout: str = "delta") -> str:
    """The standard as the study prints it: 2/3 (0.667) for the delta, 1/3 (0.333) for a tadpole."""
    limit = LAYOUTS[layout].limit if layout in LAYOUTS else LSF_LIMIT
    return f"{limit.numerator}/{limit.denominator} ({ratio(limit)})"


def axles_of(layout: str = "delta") -> Layout:
    """A layout by name, for a page that words by its tyre counts (the delta when unknown)."""
    return LAYOUTS.get(layout, DELTA)


# Each layout's title (the core's Layout.title, which speaks English only), to be translated.
_LAYOUT_TITLES = {
    "delta": N_("Delta (one front wheel and two rear wheels)"),
    "tadpole": N_("Tadpole (two front wheels and one rear wheel)"),
    "quadricycle": N_("Quadricycle (two front wheels and two rear wheels)"),
}


def layout_title(layout: str) -> str:
    """A layout's name for a person, in the active language: "Tadpole (two front wheels and one rear ...)"."""
    title = _LAYOUT_TITLES.get(layout)
    return gettext(title) if title is not None else LAYOUTS[layout].title


@lru_cache
def _zone(name: str) -> ZoneInfo | None:
    try:
        return ZoneInfo(name)
    except (ZoneInfoNotFoundError, ValueError):
        return None


def local_zone() -> ZoneInfo | None:
    """The officers' time zone from the settings (None: UTC)."""
    return _zone(get_settings().display_timezone)


def to_local(moment: datetime) -> datetime:
    """A stored UTC time in the officers' zone."""
    zone = local_zone()
    return moment.astimezone(zone) if zone else moment.astimezone(UTC)


def local_time(moment: datetime) -> str:
    """A time in the display zone, its date as `long_date` words it, the zone named:
    23 November 2026, 14:05 WAT."""
    local = to_local(moment)
    # Digits and the zone's abbreviation read the same in every language: only the date is worded.
    return f"{long_date(local.date())}, {local:%H:%M} {local.tzname() or 'UTC'}"


def long_date(moment: datetime | date) -> str:
    """Every date on the pages, the papers and the command line: 1 December 2027, in the display zone."""
    local = to_local(moment) if isinstance(moment, datetime) else moment
    locale = current_locale()
    if locale == ENGLISH:  # as it always was, whatever the machine's own locale
        return f"{local.day} {local:%B %Y}"
    # The same order in every language (1 Disamba 2027), the month's name from CLDR.
    return format_date(local if not isinstance(local, datetime) else local.date(), "d MMMM y", locale=locale)


def month_names() -> list[str]:
    """The twelve months as long_date names them in the active language (January ... December, from
    CLDR outside English): the offline checker writes its dates with them, whatever its browser knows."""
    locale = current_locale()
    if locale == ENGLISH:
        return [f"{date(2000, month, 1):%B}" for month in range(1, 13)]
    names = get_month_names("wide", "format", locale=locale)
    return [names[month] for month in range(1, 13)]


def day_bounds(day: date) -> tuple[datetime, datetime]:
    """The UTC start and end of a local calendar day."""
    zone = local_zone() or UTC
    start = datetime.combine(day, time.min, tzinfo=zone)
    return start.astimezone(UTC), (start + timedelta(days=1)).astimezone(UTC)


def local_today() -> date:
    """Today's date in the officers' zone."""
    return to_local(datetime.now(UTC)).date()
