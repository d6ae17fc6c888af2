"""The trust bundle made from the records: every trusted key with its period and the numbers it signed,
every revoked and superseded number with its date; signed with the key in force (app/trust/bundle.py
is its format). Served at /.well-known/trikecert-trust and written by `trikecert trust-bundle`.

`seq` is counted, not stored: revocations + supersessions + key rows + key retirements + withdrawals
+ endorsements. Each of those tables is append-only (or only moves forward: a key is retired once,
withdrawn once), so the sum strictly increases with every event and never needs a counter that an
insider could reset. The signed bundle is kept in memory per database and rebuilt as soon as that
count, the newest key row or (while the active key has signed none) the floor of its numbers
changes: a revocation is in the very next answer. `made_at` is the start of the current hour, so the
bundle is re-signed every hour and every worker process signs the same bytes (Ed25519 is
deterministic): the same ETag whichever worker answers a checker's conditional request.
"""

from __future__ import annotations

import gzip
import hashlib
import threading
from dataclasses import dataclass, replace
from datetime import datetime

from sqlalchemy import func, select
from sqlalchemy.orm import Session, aliased

from app.certificates.models import Certificate, CertificateAudit, CertificateRevocation, CertificateSequence
from app.config import Settings
from app.db import utcnow
from app.marks import MarkQuery
from app.trust.bundle import (
    BundleKey,
    Endorsement,
    KeyStatus,
    Mark,
    Relation,
    TrustBundle,
    make_payload,
    sign_bundle,
    yyyymmdd,
)
from app.trust.keys import current_signer, key_event_count, key_event_marks, trusted_key_rows
from app.trust.models import SigningKey
from app.trust.signing import issuer_claim
from app.trust.validity import local_date

REFRESH_SECONDS = 3600
_DIGITS = Certificate.year * 1_000_000 + Certificate.sequence


@dataclass(frozen=True)
class Built:
    """A signed bundle as served: its bytes, gzip bytes, strong ETags, and what it was built from."""

    body: bytes
    gzipped: bytes
    etag: str
    gzip_etag: str
    state: tuple[int, str]
    floor: int | None
    made_at: int
    marker: tuple[object, ...] = ()


def _count(session: Session, query: object) -> int:
    return int(session.scalar(query) or 0)  # type: ignore[call-overload]


def event_count(session: Session) -> int:
    """The bundle's `seq`: every revocation, supersession and key event so far (each table only grows)."""
    revocations = _count(session, select(func.count()).select_from(CertificateRevocation))
    supersessions = _count(
        session, select(func.count()).select_from(Certificate).where(Certificate.supersedes_id.is_not(None))
    )
    return revocations + supersessions + key_event_count(session)


# What changes whenever the bundle may have, in one statement of index look-ups: the newest certificate
# audit entry (every issue, reissue, supersession and revocation writes one, which the records'
# triggers enforce) and the small key tables.
BUNDLE_MARK = MarkQuery(select(select(func.max(CertificateAudit.id)).scalar_subquery(), *key_event_marks()))


def _state(session: Session) -> tuple[int, str]:
    """What the bundle's content follows, read cheaply: the event count and the newest key row (a
    database emptied and filled again, as the tests do, is never taken for the one before)."""
    newest = session.scalar(select(SigningKey.created_at).order_by(SigningKey.id.desc()).limit(1))
    return event_count(session), "" if newest is None else newest.isoformat()


def _hour(now: datetime) -> int:
    return int(now.timestamp()) // REFRESH_SECONDS * REFRESH_SECONDS


def _floor(session: Session, now: datetime) -> int:
    """The lowest number still to be issued: one above the newest year's last (or this year's first)."""
    row = session.execute(
        select(CertificateSequence.year, CertificateSequence.last_value).order_by(
            CertificateSequence.year.desc()
        )
    ).first()
    if row is None or row.year < now.year:
        return now.year * 1_000_000 + 1
    return int(row.year) * 1_000_000 + int(row.last_value) + 1


def _revoked(session: Session) -> dict[int, tuple[int, Mark]]:
    """Every revoked number (R, its revocation's date) and superseded one (S, its successor's issue date)."""
    revoked: dict[int, tuple[int, Mark]] = {}
    newer = aliased(Certificate)
    superseded = select(_DIGITS, newer.issued_at).join(newer, newer.supersedes_id == Certificate.id)
    for digits, at in session.execute(superseded):
        revoked[int(digits)] = (yyyymmdd(local_date(at)), "S")
    revocations = select(_DIGITS, CertificateRevocation.revoked_at).join(
        CertificateRevocation, CertificateRevocation.certificate_id == Certificate.id
    )
    for digits, at in session.execute(revocations):
        revoked[int(digits)] = (yyyymmdd(local_date(at)), "R")  # revoked outranks superseded
    return revoked


def _status(row: SigningKey, withdrawn: set[str]) -> KeyStatus:
    if row.kid in withdrawn:
        return "compromised"
    return "active" if row.active else "retired"


def _relation(value: str) -> Relation:
    return "successor" if value == "successor" else "predecessor"


def _keys(session: Session, floor: int) -> tuple[list[BundleKey], bool]:
    """The trusted keys with their periods and number ranges; True when the active key signed none yet."""
    ranges = {
        kid: (int(first), int(last), issued)
        for kid, first, last, issued in session.execute(
            select(
                Certificate.key_id, func.min(_DIGITS), func.max(_DIGITS), func.min(Certificate.issued_at)
            ).group_by(Certificate.key_id)
        )
    }
    keys, needs_floor = [], False
    trusted = trusted_key_rows(session)
    for row in trusted.rows:
        status = _status(row, trusted.withdrawn)
        first, last, issued = ranges.get(row.kid, (None, None, None))
        numbers: tuple[int, int | None] | None
        if status == "active":
            numbers = (first if first is not None else floor, None)
            needs_floor = needs_floor or first is None
        else:
            numbers = None if first is None or last is None else (first, last)
        began = min(row.created_at, issued) if issued is not None else row.created_at
        keys.append(
            BundleKey(
                kid=row.kid,
                x=str(row.public_jwk["x"]),
                status=status,
                valid_from=int(began.timestamp()),
                until=None if row.retired_at is None else int(row.retired_at.timestamp()),
                numbers=numbers,
                endorsements=tuple(
                    Endorsement(_relation(e.relation), e.signer_kid, e.at, e.signature)
                    for e in trusted.endorsements.get(row.kid, ())
                ),
            )
        )
    return keys, needs_floor


def build_bundle(session: Session, settings: Settings, now: datetime | None = None) -> Built:
    """Gather the records and sign the bundle with the key in force (records that key if new; commits)."""
    now = now or utcnow()
    signer = current_signer(session, settings)
    state = _state(session)
    seq = state[0]
    floor = _floor(session, now)
    keys, needs_floor = _keys(session, floor)
    bundle = TrustBundle(
        authority=settings.issuing_authority,
        issuer=issuer_claim(settings.base_url),
        seq=seq,
        made_at=_hour(now),
        max_age=settings.trust_max_age_hours * 3600,
        keys=tuple(keys),
        revoked=_revoked(session),
    )
    session.commit()  # a key recorded on first use
    body = sign_bundle(make_payload(bundle), kid=signer.kid, key=signer).encode("ascii")
    digest = hashlib.sha256(body).hexdigest()[:32]
    return Built(
        body=body,
        gzipped=gzip.compress(body, compresslevel=6, mtime=0),
        etag=f'"{digest}"',
        gzip_etag=f'"{digest}-gzip"',
        state=state,
        floor=floor if needs_floor else None,
        made_at=bundle.made_at,
    )


_cache: dict[str, Built] = {}
_lock = threading.Lock()


def served_bundle(session: Session, settings: Settings) -> Built:
    """The bundle for this database: the one kept in memory while nothing it lists changed, else a new
    one. A request costs one statement while no certificate or key event happened; after one (an
    issue, say) the exact state is counted, and the kept bundle stays when it did not change."""
    now = utcnow()
    marker = BUNDLE_MARK.read()
    held = _cache.get(settings.database_url)
    if held is not None and held.made_at == _hour(now):
        if held.marker == marker:
            return held
        if held.state == _state(session) and (held.floor is None or held.floor == _floor(session, now)):
            held = replace(held, marker=marker)
            _cache[settings.database_url] = held
            return held
    with _lock:  # one build at a time; those who waited take the bundle it made
        held = _cache.get(settings.database_url)
        if held is not None and held.made_at == _hour(now) and held.marker == marker:
            return held
        built = replace(build_bundle(session, settings, now), marker=marker)
        _cache[settings.database_url] = built
        return built


def is_bundle_kept(settings: Settings) -> bool:
    """Whether a bundle is kept for this database (it may since have gone stale)."""
    return settings.database_url in _cache


def held_bundle(settings: Settings, marker: tuple[object, ...]) -> Built | None:
    """The bundle kept for this database if it was made this hour under this mark, else None."""
    held = _cache.get(settings.database_url)
    if held is not None and held.made_at == _hour(utcnow()) and held.marker == marker:
        return held
    return None


def forget_bundles() -> None:
    """Drop every bundle kept in memory (tests, and a key withdrawn from the command line)."""
    _cache.clear()
