"""Fixed request windows: a limit per window, the window a moment falls in, the seconds until it closes.

Shared by the per-station-key limit (app/stations/rate_limit.py, counted in the database) and the
per-address limits of the anonymous doors (app/api/address_limits.py, counted in memory).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class RateLimit:
    """At most `limit` requests per `window_seconds` per station key; a limit of 0 is no limit."""

    limit: int
    window_seconds: int


def window_start(limit: RateLimit, now: float) -> int:
    """Unix seconds at which the window holding `now` opened."""
    return int(now // limit.window_seconds) * limit.window_seconds


def seconds_left(limit: RateLimit, started: int, now: float) -> int:
    """Whole seconds (at least 1) until the window opened at `started` closes: the Retry-After."""
    return max(1, math.ceil(started + limit.window_seconds - now))
