"""Deadlines for reading a request: its headers, then its body, each whole within a number of seconds.

uvicorn (0.55) times out only the idle time between two requests of a kept-alive connection, and that
timer is cancelled by the first byte that arrives (encode/uvicorn#157: no `timeout-request-start`).
A client that sends one byte a second, or connects and sends nothing, holds its socket for as long
as it likes. An ASGI middleware cannot help: the application is called only once the headers are
complete. So the guard sits in uvicorn's HTTP protocol, one timer per connection:

- from the first byte of a request (or the connection's opening) its headers must be complete within
  `header_timeout_seconds`, and no larger than MAX_HEADER_BYTES (httptools itself sets no bound);
- from then its body must be complete within `body_timeout_seconds` (a deadline for the whole body,
  not for the gap between two reads, which one byte a second would reset).

A client past a deadline is answered 408 (431 for headers too large) in the API's error shape, and
the connection is closed. Once a request is read whole, no timer runs: a slow answer is never cut.
"""

from __future__ import annotations

import asyncio
import json
import logging
from typing import Any

from uvicorn.protocols.http.h11_impl import H11Protocol

from app.config import get_settings

try:
    from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol
except ImportError:  # pragma: no cover  (httptools is optional for uvicorn)
    HttpToolsProtocol = None  # type: ignore[assignment,misc]

# Far above any request of the service (a browser's headers and cookies come to about 2 KiB).
MAX_HEADER_BYTES = 32 * 1024
logger = logging.getLogger("trikecert.access")


def refusal(status: int, reason: str, field: str, rule: str, message: str) -> bytes:
    """A whole HTTP/1.1 response in the API's error shape that closes the connection."""
    body = json.dumps({"detail": message, "errors": [{"field": field, "rule": rule, "message": message}]})
    head = (
        f"HTTP/1.1 {status} {reason}\r\ncontent-type: application/json\r\n"
        f"content-length: {len(body)}\r\nconnection: close\r\n\r\n"
    )
    return (head + body).encode()


class ReadDeadlines:
    """A mixin for a uvicorn HTTP protocol: a request's headers, then its body, each read whole in time."""

    # The attributes of uvicorn's protocols this mixin reads (both implementations have them).
    transport: asyncio.Transport
    cycle: Any
    client: tuple[str, int] | None

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        settings = get_settings()
        self._header_timeout = settings.header_timeout_seconds
        self._body_timeout = settings.body_timeout_seconds
        self._phase: str | None = None  # "headers" or "body" while a deadline runs
        self._timer: asyncio.TimerHandle | None = None
        self._reading: Any = None  # the cycle that was current when the headers' deadline started
        self._header_bytes = 0

    def connection_made(self, transport: Any) -> None:
        """A connection that never sends a byte is closed after the headers' deadline too."""
        super().connection_made(transport)  # type: ignore[misc]
        self._start("headers", self._header_timeout)

    def data_received(self, data: bytes) -> None:
        """Feed uvicorn's parser, starting and ending the deadlines as the request's parts arrive."""
        if self._phase is None and (self.cycle is None or self.cycle.response_complete):
            self._start("headers", self._header_timeout)  # the first byte of the next request
        if self._phase == "headers":
            self._header_bytes += len(data)
        super().data_received(data)  # type: ignore[misc]
        if self._phase == "headers":
            if self.cycle is not None and self.cycle is not self._reading:  # the headers are complete
                self._stop()
                if self.cycle.more_body and not self.cycle.response_complete:
                    self._start("body", self._body_timeout)
            elif self._header_bytes > MAX_HEADER_BYTES:
                self._refuse(
                    refusal(
                        431,
                        "Request Header Fields Too Large",
                        "headers",
                        "max_size",
                        f"headers: the request's headers are larger than {MAX_HEADER_BYTES // 1024} KiB",
                    )
                )
        if self._phase == "body" and not self.cycle.more_body:
            self._stop()

    def connection_lost(self, exc: Exception | None) -> None:
        """No timer outlives its connection."""
        self._stop()
        super().connection_lost(exc)  # type: ignore[misc]

    def _start(self, phase: str, seconds: float) -> None:
        self._stop()
        self._phase, self._reading, self._header_bytes = phase, self.cycle, 0
        self._timer = asyncio.get_running_loop().call_later(seconds, self._expired)

    def _stop(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
        self._timer, self._phase = None, None

    def _expired(self) -> None:
        part = "headers" if self._phase == "headers" else "body"
        seconds = self._header_timeout if part == "headers" else self._body_timeout
        self._timer = None
        logger.warning(
            "request %s not received whole within %g s: connection closed",
            part,
            seconds,
            extra={"fields": {"client": self.client[0] if self.client else None, "rule": "read_timeout"}},
        )
        answered = part == "body" and self.cycle is not None and self.cycle.response_started
        message = f"{part}: the request's {part} did not arrive whole within {seconds:g} s"
        self._refuse(None if answered else refusal(408, "Request Timeout", part, "read_timeout", message))

    def _refuse(self, response: bytes | None) -> None:
        """Answer (unless the application already began to) and close the connection."""
        self._stop()
        if self.cycle is not None and not self.cycle.response_complete:
            self.cycle.disconnected = True  # the application's own answer, if any comes, is dropped
        if not self.transport.is_closing():
            if response is not None:
                self.transport.write(response)
            self.transport.close()


class GuardedH11Protocol(ReadDeadlines, H11Protocol):
    """uvicorn's h11 protocol with read deadlines."""


if HttpToolsProtocol is not None:

    class GuardedHttpToolsProtocol(ReadDeadlines, HttpToolsProtocol):
        """uvicorn's httptools protocol with read deadlines."""


def guarded_protocol() -> str:
    """The import path of the guarded protocol, on the parser uvicorn itself would choose ("auto")."""
    name = "GuardedHttpToolsProtocol" if HttpToolsProtocol is not None else "GuardedH11Protocol"
    return f"{__name__}:{name}"
