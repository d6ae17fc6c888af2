"""Certificate dates: the expiry a number of calendar months after issue, and dates as printed."""

from __future__ import annotations

import calendar
from datetime import date, datetime

from app.web.formatting import to_local


def add_months(moment: datetime, months: int) -> datetime:
    """The same time of day `months` calendar months later (31 Jan + 1 month -> 28 or 29 Feb)."""
    index = moment.month - 1 + months
    year, month = moment.year + index // 12, index % 12 + 1
    day = min(moment.day, calendar.monthrange(year, month)[1])
    return moment.replace(year=year, month=month, day=day)


def local_date(moment: datetime) -> date:
    """The calendar date of a moment in the service's display time zone (as printed on the certificate)."""
    return to_local(moment).date()
