"""Sign-in attempts: logged to a table and the Python log (never the password), and the lock-out rule:
every password check is counted, atomically, before the password is verified."""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass

from sqlalchemy import case, update
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import Session

from app.accounts.models import LoginAttempt, LoginThrottle
from app.config import Settings
from app.db import begin_write

log = logging.getLogger("trikecert.accounts.login")

SUCCESS = "success"
BAD_CREDENTIALS = "bad_credentials"
LOCKED_OUT = "locked_out"
DISABLED = "disabled"
# An office behind one address may hold several officers: allow it this many times one account's failures.
ADDRESS_FACTOR = 4


def record_attempt(
    session: Session, *, email: str, outcome: str, user_id: int | None, client_ip: str | None
) -> None:
    """Store one attempt and log it."""
    session.add(LoginAttempt(email=email[:254], user_id=user_id, client_ip=client_ip, outcome=outcome))
    session.commit()
    level = logging.INFO if outcome == SUCCESS else logging.WARNING
    log.log(level, "sign-in %s for %r from %s", outcome, email[:254], client_ip or "unknown address")


@dataclass(frozen=True)
class ClaimedCheck:
    """The counters that one password check was counted against, to be settled once it is decided."""

    keys: tuple[str, ...]


def claim_check(
    session: Session, *, email: str, client_ip: str | None, settings: Settings, now: float | None = None
) -> ClaimedCheck | None:
    """Count one password check against the email and the client address, each in one atomic step;
    None (locked out) when either has used up its allowance within the lock-out window.

    The email may be checked `login_max_failures` times; an address, several times that many (an
    office behind one address may hold several officers, but one address trying password after
    password on many accounts is stopped too).
    """
    limits = [(f"email:{email}", settings.login_max_failures)]
    if client_ip is not None:
        limits.append((f"address:{client_ip}", settings.login_max_failures * ADDRESS_FACTOR))
    return _claim(session, limits, settings=settings, now=now)


def claim_key(session: Session, *, key: str, limit: int, settings: Settings) -> ClaimedCheck | None:
    """Count one check against a single key (a second-factor code of one account, say); None when
    its allowance is used up within the lock-out window."""
    return _claim(session, [(key, limit)], settings=settings, now=None)


def _claim(
    session: Session, limits: Sequence[tuple[str, int]], *, settings: Settings, now: float | None
) -> ClaimedCheck | None:
    """Count one check against each key in turn; at the first over its limit, give back the counts
    already taken (no check is made) and answer None."""
    moment = int(time.time() if now is None else now)
    window = settings.login_lockout_minutes * 60
    claimed: list[str] = []
    for key, limit in limits:
        if _count(session, key=key, limit=limit, window=window, now=moment) > limit:
            _give_back(session, claimed)
            return None
        claimed.append(key)
    return ClaimedCheck(keys=tuple(claimed))


def settle_check(session: Session, check: ClaimedCheck, *, outcome: str) -> None:
    """Once the password is decided: a wrong one keeps its count; a right one clears the email's
    count (a success ends the run of failures) and is given back to the address."""
    if outcome == BAD_CREDENTIALS:
        return
    email_key, *address_keys = check.keys
    begin_write(session)
    if outcome == SUCCESS:
        session.execute(update(LoginThrottle).where(LoginThrottle.key == email_key).values(checks=0))
        _give_back(session, address_keys)
    else:
        _give_back(session, check.keys)
    session.commit()


def _count(session: Session, *, key: str, limit: int, window: int, now: int) -> int:
    """Count one check against `key` and read the count back, in one statement; a count whose last
    check is older than the window starts again. Checks beyond the limit do not extend the window."""
    dialect = session.get_bind().dialect.name
    insert = postgresql.insert if dialect == "postgresql" else sqlite.insert
    row = LoginThrottle
    lapsed = row.last_counted_at < now - window
    statement = (
        insert(row)
        .values(key=key, checks=1, last_counted_at=now)
        .on_conflict_do_update(
            index_elements=[row.key],
            set_={
                "checks": case((lapsed, 1), else_=row.checks + 1),
                "last_counted_at": case((lapsed | (row.checks < limit), now), else_=row.last_counted_at),
            },
        )
        .returning(row.checks)
    )
    begin_write(session)
    count = int(session.execute(statement).scalar_one())
    session.commit()
    return count


def _give_back(session: Session, keys: Sequence[str]) -> None:
    """Take back one counted check from each key."""
    if not keys:
        return
    begin_write(session)
    session.execute(
        update(LoginThrottle)
        .where(LoginThrottle.key.in_(keys), LoginThrottle.checks > 0)
        .values(checks=LoginThrottle.checks - 1)
    )
    session.commit()
