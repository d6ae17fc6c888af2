"""The public verification's answers kept per process, each served again only while the records say
nothing changed: the newest certificate audit entry (every issue, reissue, supersession and revocation
writes one, which the records' triggers enforce) is read on every request, one index look-up, and an
answer is never kept past the moment its verdict would change by the clock (a paper's expiry).

Each worker keeps its own; correctness rests on the mark read from the database, never on a message
between processes. Only answers that are the same for everyone are kept: no scanned payload, no
signed-in session; the key includes the language the answer is in."""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime
from functools import lru_cache

from sqlalchemy import func, select
from starlette.responses import Response

from app.certificates.models import Certificate, CertificateAudit
from app.certificates.records import certificate_status
from app.config import get_settings
from app.db import utcnow
from app.i18n.active import current_locale
from app.marks import Mark, MarkQuery
from app.trust.numbers import InvalidNumber, parse_number

MAX_ANSWERS = 4096  # a flood of distinct numbers evicts the oldest, and costs only a render each


@dataclass(frozen=True)
class Kept:
    """One answer as sent: its status, body and headers (in order), with the mark it was made under."""

    mark: Mark
    until: datetime | None
    status_code: int
    body: bytes
    headers: tuple[tuple[bytes, bytes], ...]

    def response(self) -> Response:
        """A fresh response with the kept bytes and headers."""
        response = Response(self.body, status_code=self.status_code)
        response.raw_headers = list(self.headers)
        return response


_kept: OrderedDict[tuple[object, ...], Kept] = OrderedDict()
_lock = threading.Lock()


# What changes with every issue, reissue, supersession and revocation: the newest audit entry.
CHANGE_MARK = MarkQuery(select(func.max(CertificateAudit.id)))


def verdict_until(certificate: Certificate) -> datetime | None:
    """The moment this paper's verdict changes by the clock alone: its expiry while it stands."""
    return certificate.expires_at if certificate_status(certificate) == "issued" else None


@lru_cache(maxsize=MAX_ANSWERS)
def canonical_number(number: str) -> str | None:
    """The number as printed (check letter verified), or None when it does not parse."""
    try:
        return str(parse_number(number))
    except InvalidNumber:
        return None


def answer_key(kind: str, number: str) -> tuple[object, ...] | None:
    """(database, kind, normalised number, language), or None for a number that does not parse."""
    canonical = canonical_number(number)
    if canonical is None:
        return None
    return (get_settings().database_url, kind, canonical, current_locale())


def is_kept(key: tuple[object, ...]) -> bool:
    """Whether an answer is kept under this key (it may since have gone stale)."""
    return key in _kept


def held_answer(key: tuple[object, ...], mark: Mark) -> Kept | None:
    """The answer kept under this key if it was made under this mark and its verdict stands by the clock."""
    held = _kept.get(key)
    if held is not None and held.mark == mark and (held.until is None or utcnow() < held.until):
        return held
    return None


def kept_answer(kind: str, number: str, make: Callable[[], tuple[Response, datetime | None]]) -> Response:
    """The answer kept for this number while nothing changed and its verdict stands by the clock,
    else a new one from `make` (which returns the answer and the moment its verdict would change)."""
    key = answer_key(kind, number)
    if key is None:
        return make()[0]
    mark = CHANGE_MARK.read()  # before the answer is made: a change after it makes the next one anew
    held = held_answer(key, mark)
    if held is not None:
        return held.response()
    response, until = make()
    if 200 <= response.status_code < 500 and response.body is not None:
        headers = tuple(response.raw_headers)
        with _lock:
            _kept[key] = Kept(mark, until, response.status_code, bytes(response.body), headers)
            _kept.move_to_end(key)
            while len(_kept) > MAX_ANSWERS:
                _kept.popitem(last=False)
    return response


def forget_answers() -> None:
    """Drop every kept answer (tests that empty the database: its marks can repeat)."""
    with _lock:
        _kept.clear()
