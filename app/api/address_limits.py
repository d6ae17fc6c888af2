"""Per-address limits of the anonymous doors: the same fixed windows as the station key's limit
(app/stations/rate_limit.py), counted in the process's memory instead of the database.

A station's limit is a quota of a known client, exact across workers, so it is counted in a database
row its request already reads. These doors are anonymous (the public verification, a key no station
holds): a database write per request would give anyone a write path, on SQLite the writer's turn
every submission waits for. A dictionary costs a lock and a look-up. The price: each worker process
counts on its own (each application object: a test's fresh one starts from nothing), so with W
workers an address may get up to W times the limit (docs/deployment.md).
"""

from __future__ import annotations

import ipaddress
import threading
import time

from starlette.types import Scope

from app.api.windows import RateLimit, seconds_left, window_start

# Beyond this many addresses in one window, new ones are not counted: memory stays bounded, and a
# client holding that many addresses is not one a per-address limit could stop anyway.
MAX_ADDRESSES = 100_000
clock = time.time  # the windows' clock (tests hold it still, so no window turns mid-test)


def client_address(scope: Scope) -> str:
    """The address a request came from, as uvicorn gives it: the proxy's X-Forwarded-For only when
    the proxy is in TRIKECERT_FORWARDED_ALLOW_IPS. An IPv6 address counts as its /64 (one
    subscriber's network: a client picks any address inside it)."""
    client = scope.get("client")
    host = str(client[0]) if client else ""
    if ":" in host:
        try:
            return str(ipaddress.IPv6Network((host, 64), strict=False))
        except ValueError:
            return host
    return host


class AddressWindows:
    """Requests per address in the current fixed window of `limit`; safe from several threads."""

    def __init__(self, limit: RateLimit, *, max_addresses: int = MAX_ADDRESSES) -> None:
        self.limit = limit
        self.max_addresses = max_addresses
        self._lock = threading.Lock()
        self._started = -1
        self._counts: dict[str, int] = {}

    def count(self, address: str, now: float | None = None) -> int | None:
        """Count one request of `address`: None while within the limit, else the seconds to wait."""
        if self.limit.limit <= 0:
            return None
        now = clock() if now is None else now
        started = window_start(self.limit, now)
        with self._lock:
            if started > self._started:  # a new window: every address starts again from nothing
                self._started, self._counts = started, {}
            elif started < self._started:  # timed just before the window turned: the newer one
                started = self._started
            count = self._counts.get(address, 0) + 1
            if count == 1 and len(self._counts) >= self.max_addresses:
                return None
            self._counts[address] = count
        return seconds_left(self.limit, started, now) if count > self.limit.limit else None


def windows(scope: Scope, door: str, limit: RateLimit) -> AddressWindows:
    """The counters of one door under this limit, kept by the application serving the request (new
    ones when the settings change; a test's fresh application starts from nothing)."""
    state = scope["app"].state
    kept: dict[tuple[str, RateLimit], AddressWindows] | None = getattr(state, "address_windows", None)
    if kept is None:
        kept = state.address_windows = {}
    found = kept.get((door, limit))
    if found is None:
        found = kept[(door, limit)] = AddressWindows(limit)
    return found
