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

from sqlalchemy import func, select
from sqlalchemy.orm import Session
from starlette.responses import Response

from app.certificates.models import Certificate, CertificateAudit
from app.certificates.records import certificate_status
from app.config import get_settings
from app.db import utcnow
from app.i18n.active import current_locale
from app.trust.numbers import InvalidNumber, parse_number

MAX_ANSWERS = 4096  # a flood of distinct numbers evicts the oldest, and costs only a render each

# Headers the response computes from its body again.
_RECOMPUTED = {"content-length"}


@dataclass(frozen=True)
class Kept:
    """One answer as sent: its status, body and headers, with the mark it was made under."""

    mark: object
    until: datetime | None
    status_code: int
    body: bytes
    headers: tuple[tuple[str, str], ...]

    def response(self) -> Response:
        """A fresh response with the kept bytes and headers."""
        response = Response(self.body, status_code=self.status_code)
        for name, value in self.headers:
            response.headers.append(name, value)
        return response


_kept: OrderedDict[tuple[object, ...], Kept] = OrderedDict()
_lock = threading.Lock()


def change_mark(session: Session) -> object:
    """What changes with every issue, reissue, supersession and revocation: the newest audit entry."""
    return session.scalar(select(func.max(CertificateAudit.id)))


def verdict_until(certificate: Certificate) -> datetime | None:
    """The moment this paper's verdict changes by the clock alone: its expiry while it stands."""
    return certificate.expires_at if certificate_status(certificate) == "issued" else None


def answer_key(kind: str, number: str) -> tuple[object, ...] | None:
    """(database, kind, normalised number, language), or None for a number that does not parse."""
    try:
        canonical = str(parse_number(number))
    except InvalidNumber:
        return None
    return (get_settings().database_url, kind, canonical, current_locale())


def kept_answer(
    session: Session, kind: str, number: str, make: Callable[[], tuple[Response, datetime | None]]
) -> Response:
    """The answer kept for this number while nothing changed and its verdict stands by the clock,
    else a new one from `make` (which returns the answer and the moment its verdict would change)."""
    key = answer_key(kind, number)
    if key is None:
        return make()[0]
    mark = change_mark(session)
    held = _kept.get(key)
    if held is not None and held.mark == mark and (held.until is None or utcnow() < held.until):
        return held.response()
    response, until = make()
    if 200 <= response.status_code < 500 and response.body is not None:
        headers = tuple(
            (name.decode("latin-1"), value.decode("latin-1"))
            for name, value in response.raw_headers
            if name.decode("latin-1").lower() not in _RECOMPUTED
        )
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
