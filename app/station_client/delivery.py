"""Send every queued weighing until the service has answered it, backing off while it cannot."""

from __future__ import annotations

import random
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

from app.station_client.http import Answer, Verdict
from app.station_client.outbox import Outbox, Queued


@dataclass(frozen=True)
class Backoff:
    """Exponential backoff with jitter, capped; a server's Retry-After is always honoured."""

    base: float = 0.5
    cap: float = 60.0
    rng: random.Random = field(default_factory=random.SystemRandom)

    def delay(self, attempt: int, retry_after: float | None = None) -> float:
        """Seconds to wait before try `attempt + 1`: between half and all of min(cap, base * 2**attempt)."""
        ceiling = min(self.cap, self.base * 2 ** min(attempt, 30))
        jittered = self.rng.uniform(ceiling / 2, ceiling)
        return max(jittered, retry_after or 0.0)


@dataclass
class RunReport:
    """What one run did: delivered and rejected weighings, what is still queued, and why it stopped."""

    delivered: list[tuple[Queued, Answer]] = field(default_factory=list)
    rejected: list[tuple[Queued, Answer]] = field(default_factory=list)
    pending: list[Queued] = field(default_factory=list)
    stopped: str | None = None  # why weighings are left queued (unreachable, key refused)
    failed_tries: Counter[str] = field(default_factory=Counter)  # tries without a final answer, by cause


def deliver(
    outbox: Outbox,
    *,
    send: Callable[[Queued], Answer],
    backoff: Backoff,
    give_up_after: float,
    sleep: Callable[[float], None] = time.sleep,
    clock: Callable[[], float] = time.monotonic,
    say: Callable[[str], None] = print,
) -> RunReport:
    """Send the pending weighings oldest first; each is retried until answered, or until the service
    has not answered anything for `give_up_after` seconds (the rest stay queued for the next run)."""
    report = RunReport()
    last_answer = clock()
    for weighing in outbox.pending():
        attempt = 0
        while True:
            answer = send(weighing)
            if answer.verdict is Verdict.DELIVERED:
                outbox.mark_delivered(
                    weighing.id, inspection_id=answer.inspection_id, http_status=answer.status or 0
                )
                report.delivered.append((outbox.get(weighing.id), answer))
                say(
                    _line(
                        "delivered",
                        weighing,
                        f"inspection {answer.inspection_id}" + (" (replayed)" if answer.replayed else ""),
                    )
                )
                break
            if answer.verdict is Verdict.REJECTED:
                outbox.mark_rejected(weighing.id, http_status=answer.status or 0, message=answer.message)
                report.rejected.append((outbox.get(weighing.id), answer))
                say(
                    _line(
                        "rejected", weighing, f"{answer.status}: {answer.message}; {retry_hint(weighing.id)}"
                    )
                )
                break
            outbox.note_attempt(weighing.id, answer.message)
            if answer.verdict is Verdict.RETRY:
                report.failed_tries[answer.cause or "other"] += 1
            if answer.verdict is Verdict.UNAUTHORIZED:
                report.stopped = f"the service refused the station key ({answer.status}): {answer.message}"
                report.pending = outbox.pending()
                return report
            wait = backoff.delay(attempt, answer.retry_after)
            if clock() + wait - last_answer > give_up_after:
                asked = f" (it asked to wait {answer.retry_after:g} s)" if answer.retry_after else ""
                report.stopped = (
                    f"gave up after {give_up_after:g} s without an answer{asked}: {answer.message}"
                )
                report.pending = outbox.pending()
                return report
            say(
                _line(
                    "waiting",
                    weighing,
                    f"{answer.status or 'no answer'}: {answer.message}; retry in {wait:.1f} s",
                )
            )
            sleep(wait)
            attempt += 1
        last_answer = clock()
    report.pending = outbox.pending()
    return report


def retry_hint(weighing_id: int) -> str:
    """How to send a rejected weighing again once its cause is fixed."""
    return f"once the cause is fixed, send it again with: trikecert-station retry {weighing_id}"


def _line(what: str, weighing: Queued, detail: str) -> str:
    return f"{what:<9} #{weighing.id:<5} {weighing.registration_number:<12} {detail}"
