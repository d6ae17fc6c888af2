"""Request ids, access logs as JSON lines, and request metrics, in one ASGI middleware."""

from __future__ import annotations

import atexit
import json
import logging
import os
import random
import re
import time
from functools import lru_cache
from logging.handlers import QueueHandler
from typing import Any

from prometheus_client import Counter, Histogram
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.ops.log_writer import BatchWriter

REQUEST_ID_HEADER = b"x-request-id"
_VALID_ID = re.compile(rb"^[A-Za-z0-9._-]{1,64}$")
logger = logging.getLogger("trikecert.access")

REQUESTS = Counter("trikecert_http_requests_total", "HTTP requests answered", ["method", "handler", "status"])
LATENCY = Histogram(
    "trikecert_http_request_duration_seconds",
    "Time to answer an HTTP request",
    ["method", "handler"],
    buckets=(0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0),
)


class JsonFormatter(logging.Formatter):
    """One JSON object per log line, with whatever `extra` fields the record carries."""

    _second = -1
    _stamp = ""

    def format(self, record: logging.LogRecord) -> str:
        """The record as a JSON line."""
        second = int(record.created)
        if second != self._second:  # the stamp is to the second: made once per second, not per line
            self._second, self._stamp = second, self.formatTime(record, "%Y-%m-%dT%H:%M:%S%z")
        entry: dict[str, Any] = {
            "time": self._stamp,
            "level": record.levelname.lower(),
            "logger": record.name,
            "message": record.getMessage(),
        }
        entry.update(getattr(record, "fields", {}))
        if record.exc_info:
            entry["exception"] = self.formatException(record.exc_info)
        return json.dumps(entry, default=str)


class _HandOver(QueueHandler):
    """Queue the record as it is: the log writer formats and writes it, off the request's path."""

    def prepare(self, record: logging.LogRecord) -> logging.LogRecord:
        """The record itself (a thread's queue needs no pickling, so nothing is formatted here)."""
        return record


_writer: BatchWriter | None = None


def configure_logging(level: int = logging.INFO) -> None:
    """Send the app's logs to standard error as JSON lines, written by a thread of their own.

    A request only queues its line; one writer thread per process formats and writes them, a batch
    at a time (app/ops/log_writer.py), and writes what is left when the process exits.
    """
    global _writer
    if _writer is None:
        _writer = BatchWriter(JsonFormatter())
        _writer.start()
        atexit.register(_writer.stop)
    root = logging.getLogger("trikecert")
    root.handlers[:] = [_HandOver(_writer.queue)]
    root.setLevel(level)
    root.propagate = False


def flush_logs() -> None:
    """Write every line queued so far, now."""
    if _writer is not None:
        _writer.flush()


# New request ids: 128 random bits from a generator of this process's own, seeded from the system's
# randomness and again in each forked worker. An id only tells requests apart in the logs (it is no
# secret), and uuid4's system call per request cost a probe a tenth of its time.
_new_ids = random.Random()  # noqa: S311  (not a secret: see above)
os.register_at_fork(after_in_child=_new_ids.seed)


def request_id_of(scope: Scope) -> str:
    """The request's id: the caller's X-Request-ID when it is sane, else a new random one."""
    given = b""
    for name, value in scope.get("headers", ()):
        if name == REQUEST_ID_HEADER:
            given = value  # the last one, if sent twice
    return given.decode() if _VALID_ID.match(given) else f"{_new_ids.getrandbits(128):032x}"


@lru_cache(maxsize=1024)  # method x handler x status: a few hundred at most
def _counter(method: str, handler: str, status: int) -> Any:
    return REQUESTS.labels(method, handler, str(status))


@lru_cache(maxsize=1024)
def _timer(method: str, handler: str) -> Any:
    return LATENCY.labels(method, handler)


def record_request(scope: Scope, *, request_id: str, handler: str, status: int, started: float) -> None:
    """Count and time an answered request, and queue its access log line."""
    elapsed = time.perf_counter() - started
    method = scope.get("method", "")
    _counter(method, handler, status).inc()
    _timer(method, handler).observe(elapsed)
    if logger.isEnabledFor(logging.INFO):
        fields = {
            "request_id": request_id,
            "method": method,
            "path": scope.get("path", ""),
            "handler": handler,
            "status": status,
            "duration_ms": round(elapsed * 1000, 2),
        }
        # The record made directly: logger.info() would walk the stack for the caller's file and
        # line on every request, which an access line does not show.
        record = logger.makeRecord(logger.name, logging.INFO, __file__, 0, "request", (), None)
        record.fields = fields
        logger.handle(record)


class RequestContext:
    """Give every request an id (kept from X-Request-ID when sane), echo it, log and count it."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Wrap one request."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        request_id = request_id_of(scope)
        scope.setdefault("state", {})["request_id"] = request_id
        started = time.perf_counter()
        status = 500

        async def send_with_id(message: Message) -> None:
            nonlocal status
            if message["type"] == "http.response.start":
                status = message["status"]
                message.setdefault("headers", [])
                message["headers"] = [*message["headers"], (REQUEST_ID_HEADER, request_id.encode())]
            await send(message)

        try:
            await self.app(scope, receive, send_with_id)
        finally:
            # The endpoint's function name: stable, low-cardinality, and known even for nested routers.
            handler = getattr(scope.get("endpoint"), "__name__", "unmatched")
            record_request(scope, request_id=request_id, handler=handler, status=status, started=started)
