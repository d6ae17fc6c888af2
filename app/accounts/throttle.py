"""Sign-in attempts: logged to a table and the Python log (never the password), and the lock-out rule:
every password check is counted, atomically, before the password is verified.

The rule is built so that an attacker cannot turn it on everyone (OWASP ASVS 5.0 V6.1.1, V6.3.1):
- an account may be tried `login_max_failures` times; then each further check waits a delay that
  doubles (`login_lockout_minutes`, twice that, four times, ... up to MAX_DOUBLINGS), so guessing one
  account's password stays hopeless while its owner is held up only as long as someone keeps trying;
- an address is stopped only at `login_address_max_failures` (many times one account's allowance):
  behind carrier-grade NAT or an office proxy, one person's wrong guesses at other emails never stop
  a colleague who has the right password;
- a signed-in session's re-authentication counts against that session alone (app/accounts/reauth.py),
  so a lock-out of the account ends no session and stops no officer who is already signed in.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

from sqlalchemy import ColumnElement, SQLColumnExpression, case, literal, select, update
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
# The delay after the allowance doubles at most this many times (15 minutes grows to 8 hours).
MAX_DOUBLINGS = 5
ACCOUNT = "account"
ADDRESS = "address"


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
    """The counters that one password check was counted against, to be settled once it is decided:
    the account's (cleared by a success) and the others (given back by a success)."""

    account_key: str
    other_keys: tuple[str, ...] = ()


@dataclass(frozen=True)
class LockedOut:
    """No check was made: `scope` (the account, or the address) must wait `wait_seconds` first."""

    scope: str
    wait_seconds: int

    @property
    def wait_minutes(self) -> int:
        """The wait in whole minutes, rounded up (at least 1), for the message."""
        return max(1, math.ceil(self.wait_seconds / 60))


@dataclass(frozen=True)
class _Limit:
    key: str
    allowance: int
    scope: str


def claim_check(
    session: Session, *, email: str, client_ip: str | None, settings: Settings, now: float | None = None
) -> ClaimedCheck | LockedOut:
    """Count one password check against the client address, then the email, each in one atomic step;
    LockedOut when either must wait (see the module's rule).

    The address is counted first so that a locked account does not spend its delay on a check that
    its address then refuses; the address's allowance is `login_address_max_failures`.
    """
    limits = []
    if client_ip is not None:
        limits.append(_Limit(f"address:{client_ip}", settings.login_address_max_failures, ADDRESS))
    limits.append(_Limit(f"email:{email}", settings.login_max_failures, ACCOUNT))
    return _claim(session, limits, settings=settings, now=now)


def claim_key(
    session: Session, *, key: str, limit: int, settings: Settings, now: float | None = None
) -> ClaimedCheck | LockedOut:
    """Count one check against a single key (a second-factor code of one account, a session's
    re-authentication), under the same growing delays; LockedOut when it must wait."""
    return _claim(session, [_Limit(key, limit, ACCOUNT)], settings=settings, now=now)


def _claim(
    session: Session, limits: Sequence[_Limit], *, settings: Settings, now: float | None
) -> ClaimedCheck | LockedOut:
    """Count one check against each key in turn; at the first that must wait, give back the counts
    already taken (no check is made) and say how long."""
    moment = int(time.time() if now is None else now)
    base = settings.login_lockout_minutes * 60
    claimed: list[str] = []
    for limit in limits:
        if not _count(session, key=limit.key, allowance=limit.allowance, base=base, now=moment):
            _give_back(session, claimed)
            wait = _wait(session, key=limit.key, allowance=limit.allowance, base=base, now=moment)
            return LockedOut(limit.scope, wait)
        claimed.append(limit.key)
    *others, account = claimed
    return ClaimedCheck(account_key=account, other_keys=tuple(others))


def settle_check(session: Session, check: ClaimedCheck, *, outcome: str) -> None:
    """Once the password is decided: a wrong one keeps its count; a right one clears the account's
    count (a success ends the run of failures) and is given back to the address."""
    if outcome == BAD_CREDENTIALS:
        return
    begin_write(session)
    if outcome == SUCCESS:
        session.execute(update(LoginThrottle).where(LoginThrottle.key == check.account_key).values(checks=0))
        _give_back(session, check.other_keys)
    else:
        _give_back(session, (*check.other_keys, check.account_key))
    session.commit()


def delay_seconds(checks: int, *, allowance: int, base: int) -> int:
    """How long after the last counted check the next may be made: none within the allowance, then
    `base`, doubling with each further check up to MAX_DOUBLINGS."""
    if checks < allowance:
        return 0
    doublings: int = min(checks - allowance, MAX_DOUBLINGS)
    return base * (1 << doublings)


def _delay(checks: SQLColumnExpression[int], *, allowance: int, base: int) -> ColumnElement[int]:
    """`delay_seconds` as SQL (both databases): one branch per doubling."""
    whens = [(checks < allowance, literal(0))]
    whens += [
        (checks == allowance + n, literal(delay_seconds(allowance + n, allowance=allowance, base=base)))
        for n in range(MAX_DOUBLINGS)
    ]
    longest = delay_seconds(allowance + MAX_DOUBLINGS, allowance=allowance, base=base)
    return case(*whens, else_=literal(longest))


def _count(session: Session, *, key: str, allowance: int, base: int, now: int) -> bool:
    """Count one check against `key` when its delay has passed, in one statement (an upsert whose
    update applies only then); False when it must wait. A count idle for its delay and a further
    `base` is forgotten and starts again."""
    dialect = session.get_bind().dialect.name
    insert = postgresql.insert if dialect == "postgresql" else sqlite.insert
    row = LoginThrottle
    due = row.last_counted_at + _delay(row.checks, allowance=allowance, base=base)
    forgotten = due + base < now
    statement = (
        insert(row)
        .values(key=key, checks=1, last_counted_at=now)
        .on_conflict_do_update(
            index_elements=[row.key],
            set_={"checks": case((forgotten, 1), else_=row.checks + 1), "last_counted_at": now},
            where=forgotten | (due <= now),
        )
        .returning(row.checks)
    )
    begin_write(session)
    counted = session.execute(statement).scalar_one_or_none()
    session.commit()
    return counted is not None


def _wait(session: Session, *, key: str, allowance: int, base: int, now: int) -> int:
    """Seconds until `key` may be checked again (read after a refused count, for the message)."""
    found = session.execute(
        select(LoginThrottle.checks, LoginThrottle.last_counted_at).where(LoginThrottle.key == key)
    ).one_or_none()
    session.commit()
    if found is None:
        return 0
    checks, last = found
    return max(0, last + delay_seconds(checks, allowance=allowance, base=base) - now)


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
