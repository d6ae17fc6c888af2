"""How figures and times are printed on the pages: kg to 0.1, ratios to 3 decimals, local times."""

from __future__ import annotations

from datetime import UTC, date, datetime, time, timedelta
from decimal import ROUND_HALF_EVEN, Decimal
from fractions import Fraction
from functools import lru_cache
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

from app.config import get_settings
from app.stability import LSF_LIMIT


def fixed(value: Decimal | Fraction | float, places: int) -> str:
    """The value rounded half-even to `places` decimals."""
    if isinstance(value, Fraction):
        value = Decimal(value.numerator) / Decimal(value.denominator)
    exponent = Decimal(1).scaleb(-places)
    return str(Decimal(value).quantize(exponent, ROUND_HALF_EVEN))


def kg(value: Decimal | Fraction | float, places: int = 1) -> str:
    """A weight in kg, to 0.1 kg by default."""
    return fixed(value, places)


def ratio(value: Decimal | Fraction | float) -> str:
    """A ratio such as the LSF, to 3 decimals."""
    return fixed(value, 3)


def signed(value: Decimal | Fraction | float) -> str:
    """A variance with its sign, to 3 decimals: +0.009, -0.030."""
    text = fixed(value, 3)
    return text if text.startswith("-") else f"+{text}"


def limit_text() -> str:
    """The standard as the study prints it: 2/3 (0.667)."""
    return f"{LSF_LIMIT.numerator}/{LSF_LIMIT.denominator} ({ratio(LSF_LIMIT)})"


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
    """A time as officers read it: 23 Nov 2026, 14:05."""
    return to_local(moment).strftime("%d %b %Y, %H:%M").lstrip("0")


def day_bounds(day: date) -> tuple[datetime, datetime]:
    """The UTC start and end of a local calendar day."""
    zone = local_zone() or UTC
    start = datetime.combine(day, time.min, tzinfo=zone)
    return start.astimezone(UTC), (start + timedelta(days=1)).astimezone(UTC)


def local_today() -> date:
    """Today's date in the officers' zone."""
    return to_local(datetime.now(UTC)).date()
