"""One POST of a queued weighing, and what its answer means for the queue.

Whatever the network does (refuses, resets, cuts an answer short, stays silent, answers 5xx, 408,
409 or 429) is an Answer to retry, with a short cause that the run counts; nothing escapes as an
exception, so the client never stops with a traceback half-way through its queue.
"""

from __future__ import annotations

import http.client
import json
import urllib.error
import urllib.request
from dataclasses import dataclass
from datetime import UTC, datetime
from email.utils import parsedate_to_datetime
from enum import Enum
from typing import Any

from app.station_client.outbox import Queued

INSPECTIONS_PATH = "/api/v1/inspections"
UNREACHABLE = "the service could not be reached"
# Answers worth another try: a request timeout, an Idempotency-Key still in flight, the rate limit.
RETRIED_4XX = {408: "408 request timeout", 409: "409 in flight", 429: "429 too many requests"}


class Verdict(Enum):
    """What to do with a weighing after one try."""

    DELIVERED = "delivered"  # stored (201), or stored earlier and replayed
    REJECTED = "rejected"  # refused for good (4xx other than 401, 408, 409, 429): not sent again
    RETRY = "retry"  # unreachable, cut off, timed out, 5xx, 408, 409 (still in flight) or 429
    UNAUTHORIZED = "unauthorized"  # the station key was refused: stop, keep everything queued


@dataclass(frozen=True)
class Answer:
    """The service's answer to one try (status None when no answer arrived whole)."""

    verdict: Verdict
    status: int | None
    message: str
    inspection_id: int | None = None
    retry_after: float | None = None
    replayed: bool = False
    cause: str = ""  # why a retry: "connection refused", "5xx", "429 too many requests", ...


def retry_after_seconds(value: str | None, *, now: datetime | None = None) -> float | None:
    """Retry-After as seconds: a number of seconds or an HTTP date; None when absent or unreadable."""
    if not value:
        return None
    value = value.strip()
    if value.isascii() and value.isdigit():
        return float(value)
    try:
        when = parsedate_to_datetime(value)
    except (TypeError, ValueError, IndexError):
        return None
    if when.tzinfo is None:
        when = when.replace(tzinfo=UTC)
    return max(0.0, (when - (now or datetime.now(UTC))).total_seconds())


def _json(body: bytes) -> Any:
    """The body as JSON, or None when it is not (a proxy's page, a cut-off or hostile body)."""
    try:
        return json.loads(body)
    except (ValueError, RecursionError):
        return None


def _detail(body: bytes) -> str:
    data = _json(body)
    if data is None:
        return body.decode(errors="replace")[:500] or "no message"
    return str(data.get("detail", data)) if isinstance(data, dict) else str(data)


def _inspection_id(body: bytes) -> int | None:
    data = _json(body)
    value = data.get("id") if isinstance(data, dict) else None
    return value if isinstance(value, int) and not isinstance(value, bool) and value > 0 else None


def judge(status: int, headers: Any, body: bytes) -> Answer:
    """The verdict on one HTTP answer."""
    replayed = str(headers.get("Idempotent-Replayed", "")).lower() == "true"
    if 200 <= status < 300:
        inspection_id = _inspection_id(body)
        if inspection_id is None:  # not the service's answer (a proxy's page): try again
            return Answer(Verdict.RETRY, status, "the answer was not the service's JSON", cause="not JSON")
        return Answer(Verdict.DELIVERED, status, "stored", inspection_id=inspection_id, replayed=replayed)
    message = _detail(body)
    if status == 401:
        return Answer(Verdict.UNAUTHORIZED, status, message)
    if status in RETRIED_4XX or status >= 500:
        return Answer(
            Verdict.RETRY,
            status,
            message,
            retry_after=retry_after_seconds(headers.get("Retry-After")),
            cause=RETRIED_4XX.get(status, "5xx"),
        )
    return Answer(Verdict.REJECTED, status, message)


def _failure(error: BaseException) -> Answer:
    """A try that got no whole answer: why, as a cause to count and a message to show."""
    reason: Any = getattr(error, "reason", error) if isinstance(error, urllib.error.URLError) else error
    if isinstance(reason, ConnectionRefusedError):
        return Answer(Verdict.RETRY, None, f"{UNREACHABLE}: connection refused", cause="connection refused")
    if isinstance(reason, TimeoutError):
        return Answer(Verdict.RETRY, None, f"{UNREACHABLE}: no answer in time", cause="timed out")
    if isinstance(reason, http.client.IncompleteRead):
        return Answer(
            Verdict.RETRY, None, f"the answer was cut off after {len(reason.partial)} bytes", cause="cut off"
        )
    if isinstance(reason, ConnectionError | http.client.RemoteDisconnected):
        return Answer(
            Verdict.RETRY, None, f"{UNREACHABLE}: the connection was dropped ({reason})", cause="reset"
        )
    if isinstance(reason, http.client.HTTPException):
        return Answer(
            Verdict.RETRY, None, f"the answer was not HTTP ({type(reason).__name__})", cause="bad answer"
        )
    return Answer(Verdict.RETRY, None, f"{UNREACHABLE}: {reason}", cause="unreachable")


def post_weighing(base_url: str, key: str, weighing: Queued, *, timeout: float = 15.0) -> Answer:
    """POST one queued weighing with its own Idempotency-Key and judge the answer."""
    if not base_url.startswith(("http://", "https://")):
        raise ValueError(f"the service's address must start with http:// or https://, not {base_url!r}")
    request = urllib.request.Request(  # noqa: S310 (http or https, checked above)
        base_url.rstrip("/") + INSPECTIONS_PATH,
        data=weighing.body.encode(),
        headers={
            "Authorization": f"Bearer {key}",
            "Content-Type": "application/json",
            "Idempotency-Key": weighing.idempotency_key,
            "User-Agent": "trikecert-station/0.1",
        },
        method="POST",
    )
    try:
        try:
            with urllib.request.urlopen(request, timeout=timeout) as response:  # noqa: S310 (checked above)
                return judge(response.status, response.headers, response.read())
        except urllib.error.HTTPError as error:
            # An error answer's body can be cut off too (the service dying while it sends a 429).
            with error:
                return judge(error.code, error.headers, error.read())
    except (urllib.error.URLError, http.client.HTTPException, OSError) as error:
        return _failure(error)
