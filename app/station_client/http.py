"""One POST of a queued weighing, and what its answer means for the queue."""

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


class Verdict(Enum):
    """What to do with a weighing after one try."""

    DELIVERED = "delivered"  # stored (201), or stored earlier and replayed
    REJECTED = "rejected"  # refused for good (4xx other than 401, 409, 429): not sent again
    RETRY = "retry"  # unreachable, 5xx, 409 (still in flight) or 429: try again later
    UNAUTHORIZED = "unauthorized"  # the station key was refused: stop, keep everything queued


@dataclass(frozen=True)
class Answer:
    """The service's answer to one try (status None when it could not be reached)."""

    verdict: Verdict
    status: int | None
    message: str
    inspection_id: int | None = None
    retry_after: float | None = None
    replayed: bool = False


def retry_after_seconds(value: str | None, *, now: datetime | None = None) -> float | None:
    """Retry-After as seconds: a number of seconds or an HTTP date; None when absent or unreadable."""
    if not value:
        return None
    value = value.strip()
    if value.isdigit():
        return float(value)
    try:
        when = parsedate_to_datetime(value)
    except (TypeError, ValueError):
        return None
    if when.tzinfo is None:
        when = when.replace(tzinfo=UTC)
    return max(0.0, (when - (now or datetime.now(UTC))).total_seconds())


def _detail(body: bytes) -> str:
    try:
        data: Any = json.loads(body)
    except ValueError:
        return body.decode(errors="replace")[:500] or "no message"
    return str(data.get("detail", data)) if isinstance(data, dict) else str(data)


def judge(status: int, headers: Any, body: bytes) -> Answer:
    """The verdict on one HTTP answer."""
    replayed = str(headers.get("Idempotent-Replayed", "")).lower() == "true"
    if 200 <= status < 300:
        try:
            inspection_id = int(json.loads(body)["id"])
        except (ValueError, KeyError, TypeError):  # not the service's answer (a proxy's page): try again
            return Answer(Verdict.RETRY, status, "the answer was not the service's JSON")
        return Answer(Verdict.DELIVERED, status, "stored", inspection_id=inspection_id, replayed=replayed)
    message = _detail(body)
    if status == 401:
        return Answer(Verdict.UNAUTHORIZED, status, message)
    if status in (409, 429) or status >= 500:
        return Answer(
            Verdict.RETRY, status, message, retry_after=retry_after_seconds(headers.get("Retry-After"))
        )
    return Answer(Verdict.REJECTED, status, message)


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
        with urllib.request.urlopen(request, timeout=timeout) as response:  # noqa: S310 (http or https, checked above)
            return judge(response.status, response.headers, response.read())
    except urllib.error.HTTPError as error:
        with error:
            return judge(error.code, error.headers, error.read())
    except (urllib.error.URLError, http.client.HTTPException, OSError) as error:
        reason = getattr(error, "reason", error)
        return Answer(Verdict.RETRY, None, f"the service could not be reached: {reason}")
