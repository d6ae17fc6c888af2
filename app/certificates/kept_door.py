"""The public verification's kept answers, and the kept trust bundle, served ahead of the router.

A roadside scan's `GET /verify/{number}` (page or JSON) and `GET /api/v1/verify/{number}`, and the offline
checkers' conditional GET of the trust bundle, are the doors anyone can flood. Once an answer is kept
(answer_cache, trust_bundle), the same request is answered here, inside the request log, the language, the
rate limit and the headers' middleware, but before the routing, the dependencies and the thread pool: the
records' change mark is still read on every request (app/marks.py), so a revocation shows on the very next
one. Anything else (a scanned payload, a query, an answer not kept or gone stale, a database that does not
answer) goes on to the route, which answers exactly as before and keeps the answer for the next request.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from starlette.types import ASGIApp, Receive, Scope, Send

from app.certificates.answer_cache import CHANGE_MARK, Kept, answer_key, held_answer, is_kept
from app.certificates.bundle_answer import bundle_response
from app.certificates.trust_bundle import BUNDLE_MARK, Built, held_bundle, is_bundle_kept
from app.certificates.verify_json import accepts_json
from app.config import get_settings
from app.marks import Mark, MarkQuery
from app.web.scope import header

BUNDLE_PATH = "/.well-known/trikecert-trust"
PAGE_PREFIX = "/verify/"
API_PREFIX = "/api/v1/verify/"
# The routes' own bounds on the number (a longer one is the route's 422, never a kept answer).
PAGE_NUMBER_MAX, API_NUMBER_MAX = 60, 40
Held = TypeVar("Held")


def door_of(scope: Scope) -> tuple[str, str] | None:
    """(kind of kept answer, number) for a plain GET of a public verification, else None."""
    if not _plain_get(scope):
        return None
    path: str = scope["path"]
    if path.startswith(API_PREFIX):
        number = path[len(API_PREFIX) :]
        bound, kind = API_NUMBER_MAX, "api-verify"
    elif path.startswith(PAGE_PREFIX):
        number = path[len(PAGE_PREFIX) :]
        bound = PAGE_NUMBER_MAX
        kind = "verify-json" if accepts_json(header(scope, b"accept") or "") else "verify-html"
    else:
        return None
    if not number or len(number) > bound or "/" in number:
        return None
    return kind, number


class KeptAnswersFirst:
    """Serve a kept, still current public verification before the router; pass everything else on."""

    def __init__(self, app: ASGIApp, *, endpoints: dict[str, Callable[..., Any]]) -> None:
        self.app = app
        self.endpoints = endpoints  # kind -> the route's function, named in the request log

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Answer from the kept answers when one is current, else call the app."""
        if scope["type"] == "http" and scope["path"] == BUNDLE_PATH:
            await self._bundle(scope, receive, send)
            return
        door = door_of(scope) if scope["type"] == "http" else None
        key = answer_key(*door) if door is not None else None
        if door is None or key is None or not is_kept(key):
            await self.app(scope, receive, send)
            return
        held = await _current(CHANGE_MARK, lambda mark: held_answer(key, mark))
        if held is None:
            await self.app(scope, receive, send)
            return
        scope["endpoint"] = self.endpoints[door[0]]
        await send_kept(held, send)

    async def _bundle(self, scope: Scope, receive: Receive, send: Send) -> None:
        held = await current_bundle(scope)
        if held is None:
            await self.app(scope, receive, send)
            return
        scope["endpoint"] = self.endpoints["bundle"]
        if_none_match = header(scope, b"if-none-match")
        answer = bundle_response(held, header(scope, b"accept-encoding") or "", if_none_match)
        await answer(scope, receive, send)


async def current_bundle(scope: Scope) -> Built | None:
    """The kept trust bundle when this is a plain GET and the bundle is still current, else None."""
    settings = get_settings()
    if not (_plain_get(scope) and is_bundle_kept(settings)):
        return None
    return await _current(BUNDLE_MARK, lambda mark: held_bundle(settings, mark))


def _plain_get(scope: Scope) -> bool:
    """A GET with no query: the only request a kept answer is ever the answer to."""
    return scope["method"] == "GET" and not scope["query_string"]


async def _current(query: MarkQuery, pick: Callable[[Mark], Held | None]) -> Held | None:
    """What `pick` keeps under the records' mark now, or None (also when the mark cannot be read: the
    route meets the failure again and answers as it always does)."""
    try:
        return pick(await query.read_soon())
    except Exception:
        return None


async def send_kept(held: Kept, send: Send) -> None:
    """Send a kept answer as the route sent it."""
    start = {"type": "http.response.start", "status": held.status_code, "headers": list(held.headers)}
    await send(start)
    await send({"type": "http.response.body", "body": held.body})
