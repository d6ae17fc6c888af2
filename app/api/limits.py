"""The bounds of a request body: its size in bytes (an ASGI middleware answering 413), and how many
values its lists and objects it may hold (checked by app.api.strict_json as the body is parsed)."""

from __future__ import annotations

import json

from starlette.exceptions import HTTPException
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.errors import ServiceError
from app.numbers import LIMITS, MAX_LOAD_ITEMS, MAX_READINGS

# The longest list any field of the API takes (one wheel's repeated readings, the seats, the load
# items): a longer one is refused as soon as it is parsed, before any of its values is validated,
# so a 1 MiB body of half a million readings costs a JSON parse, not half a million validations.
MAX_LIST_ITEMS = max(MAX_READINGS, LIMITS.max_seats, MAX_LOAD_ITEMS)
# A valid inspection holds about 50 objects (its readings, seats, load items and measured cases).
MAX_OBJECTS = 200


def too_large_message(max_bytes: int) -> str:
    """The refusal of an oversized body, naming the field and the rule."""
    return f"body: the request body is larger than the {max_bytes / (1024 * 1024):g} MiB limit"


class BodyTooLarge(ServiceError, HTTPException):
    """Raised inside receive() when the streamed body passes the limit.

    It is an HTTPException so FastAPI's body parsing lets it through, and a ServiceError so
    it is answered in the common error shape.
    """

    status = 413

    def __init__(self, max_bytes: int) -> None:
        ServiceError.__init__(self, too_large_message(max_bytes), field="body", rule="max_size")
        self.status_code = 413
        self.detail = self.message
        self.headers = None


class BodySizeLimit:
    """Answer 413 to any request whose body is (or turns out to be) larger than `max_bytes`."""

    def __init__(self, app: ASGIApp, *, max_bytes: int) -> None:
        self.app = app
        self.max_bytes = max_bytes

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Check the declared length first, then count the bytes as they arrive."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        declared = dict(scope.get("headers", [])).get(b"content-length")
        if declared is not None and declared.isdigit():
            if int(declared) > self.max_bytes:
                await self._refuse(send)
                return
            # The server reads exactly the declared length (and refuses a body that is also
            # chunked): nothing more can arrive to count.
            await self.app(scope, receive, send)
            return
        received = 0
        started = False

        async def counting_receive() -> Message:
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.max_bytes:
                    raise BodyTooLarge(self.max_bytes)
            return message

        async def tracking_send(message: Message) -> None:
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
            await send(message)

        try:
            await self.app(scope, counting_receive, tracking_send)
        except BodyTooLarge:
            if not started:
                await self._refuse(send)

    async def _refuse(self, send: Send) -> None:
        message = too_large_message(self.max_bytes)
        body = json.dumps(
            {"detail": message, "errors": [{"field": "body", "rule": "max_size", "message": message}]}
        ).encode()
        await send(
            {
                "type": "http.response.start",
                "status": 413,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"content-length", str(len(body)).encode()),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})
