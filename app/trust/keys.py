"""Signing keys: held outside the database (a key file, a PKCS#11 token, or the configuration),
rotated, published as a JWKS.

The private key is never stored in the database: the store the settings name (signer.py) holds it,
and the `signing_key` table keeps each key's public half and metadata (kid, source, the period it
signed in), so the published key set verifies every certificate ever issued. The store is the
truth about which key signs: a key found there that the table does not know yet is recorded and
every other key retired; a key the table has retired never signs again. Each published key also
carries its COSE_Key form (`cose_key`), for the CWT payloads of the QR codes.
"""

from __future__ import annotations

import base64
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import cbor2
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from joserfc.jwk import OKPKey
from sqlalchemy import ScalarSelect, func, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from app.config import Settings, get_settings
from app.db import utcnow
from app.errors import Conflict, InvalidInput, NotFound
from app.trust.bundle import BundleRefused, Relation, b64url, endorsement_text, unb64url, verifies
from app.trust.cwt import EDDSA, kid_bytes
from app.trust.jws import ALGORITHM
from app.trust.keyfile import KeyFile, default_key_path
from app.trust.models import KeyEndorsement, KeyGrandfathered, KeyWithdrawal, SigningKey
from app.trust.signer import (
    KID_LENGTH,
    ConfiguredKey,
    KeyStore,
    KeyUnavailable,
    Signer,
    parse_private_key,
    private_pem,
)

__all__ = [
    "KID_LENGTH",
    "Signer",
    "current_signer",
    "key_store",
    "kid_of",
    "okp_key",
    "parse_private_key",
    "private_pem",
    "public_jwk",
    "published_keys",
    "rotate_signing_key",
]


def okp_key(key: Ed25519PrivateKey) -> OKPKey:
    """The joserfc key object of a private key."""
    return OKPKey.import_key(private_pem(key))


def kid_of(key: OKPKey) -> str:
    """The key id: the start of the RFC 7638 thumbprint of the public key."""
    return key.thumbprint()[:KID_LENGTH]


def public_jwk(key: OKPKey) -> dict[str, Any]:
    """The public half as a JWK."""
    public = key.as_dict(private=False)
    return {"kty": public["kty"], "crv": public["crv"], "x": public["x"]}


def key_store(settings: Settings) -> KeyStore:
    """Where the settings hold the signing key: TRIKECERT_SIGNING_KEY, else a PKCS#11 token when
    TRIKECERT_PKCS11_MODULE is set, else the key file."""
    if settings.signing_key is not None:
        return ConfiguredKey(settings.signing_key.get_secret_value())
    if settings.pkcs11_module is not None:
        from app.trust.pkcs11_token import token_store

        return token_store(settings)
    return KeyFile(default_key_path(settings))


def _retire_others(session: Session, kid: str) -> None:
    now = utcnow()
    for row in session.scalars(select(SigningKey).where(SigningKey.active.is_(True), SigningKey.kid != kid)):
        row.active = False
        row.retired_at = now


_store_kids: dict[tuple[str, ...], str] = {}


def store_kid(settings: Settings) -> str | None:
    """The id of the key the store holds now, the root of trust (None: a key file not made yet). A key
    file is read again when it changes (its size and time); a token is asked once per process, and
    again whenever this process signs or rotates (`current_signer`, `rotate_signing_key`)."""
    store = key_store(settings)
    if isinstance(store, ConfiguredKey):
        return store.current().kid
    if isinstance(store, KeyFile):
        try:
            found = store.path.stat()
        except FileNotFoundError:
            return None
        except OSError as error:
            raise KeyUnavailable(f"cannot read the signing key file {store.path}: {error}") from error
        marker: tuple[str, ...] = (
            store.describe(),
            str(found.st_mtime_ns),
            str(found.st_size),
            str(found.st_ino),
        )
    else:
        marker = (store.describe(),)
    kid = _store_kids.get(marker)
    if kid is None:
        kid = store.current().kid
        _store_kids[marker] = kid
    return kid


def _remember(store: KeyStore, kid: str) -> None:
    if not isinstance(store, KeyFile | ConfiguredKey):
        _store_kids[(store.describe(),)] = kid


def _x(row: SigningKey) -> str:
    return str(row.public_jwk["x"])


def withdrawal_text(kid: str, x: str, at: int) -> bytes:
    """The exact ASCII bytes a key's withdrawal signs (docs/verification.md)."""
    return f"trikecert-key-withdrawal:1:{kid}:{x}:{at}".encode("ascii")


@lru_cache(maxsize=4096)
def _holds(x: str, signature: str, message: bytes) -> bool:
    """An Ed25519 signature check, remembered: the statements it checks are never changed."""
    try:
        raw = unb64url(signature, "signature")
    except BundleRefused:
        return False
    return verifies(x, raw, message)


@dataclass(frozen=True)
class TrustedKeys:
    """The key rows this service vouches for, oldest first; the endorsements about each (by subject kid,
    only those signed by a trusted key); the kids withdrawn for compromise (still listed, as such)."""

    rows: list[SigningKey]
    endorsements: dict[str, list[KeyEndorsement]] = field(default_factory=dict)
    withdrawn: set[str] = field(default_factory=set)


def chain_of_trust(
    rows: Sequence[SigningKey],
    statements: Sequence[KeyEndorsement],
    withdrawals: Sequence[KeyWithdrawal],
    root: str | None,
) -> TrustedKeys:
    """The keys reached from `root` (the store's key) through statements signed by keys already reached:
    a `predecessor` statement vouches for the key before, the first valid `successor` statement of a
    key for the key after it (a process that has not seen a rotation yet still trusts the new key). A
    withdrawal signed by a reached key (not the withdrawn one) marks a key compromised; statements a
    withdrawn key signed then count for nothing. Any other row (one an insider inserted) is left out."""
    by_kid = {row.kid: row for row in rows}

    def valid(statement: KeyEndorsement) -> bool:
        signer, subject = by_kid.get(statement.signer_kid), by_kid.get(statement.subject_kid)
        if signer is None or subject is None or signer.kid == subject.kid:
            return False
        text = endorsement_text(statement.relation, signer.kid, subject.kid, _x(subject), statement.at)  # type: ignore[arg-type]
        return _holds(_x(signer), statement.signature, text)

    first_successor: dict[str, int] = {}
    for statement in statements:
        if (
            statement.relation == "successor"
            and statement.signer_kid not in first_successor
            and valid(statement)
        ):
            first_successor[statement.signer_kid] = statement.id

    def reach(ignored: set[str]) -> set[str]:
        reached = {root} if root in by_kid else set()
        grew = True
        while grew:
            grew = False
            for statement in statements:
                signer, subject = statement.signer_kid, statement.subject_kid
                if signer not in reached or signer in ignored or subject in reached:
                    continue
                if statement.relation == "successor" and first_successor.get(signer) != statement.id:
                    continue
                if valid(statement):
                    reached.add(subject)
                    grew = True
        return reached

    first = reach(set())
    withdrawn = {
        w.kid
        for w in withdrawals
        if w.kid in first
        and w.signer_kid in first
        and w.signer_kid != w.kid
        and _holds(_x(by_kid[w.signer_kid]), w.signature, withdrawal_text(w.kid, _x(by_kid[w.kid]), w.at))
    }
    trusted = reach(withdrawn) | withdrawn
    endorsements: dict[str, list[KeyEndorsement]] = {}
    for statement in statements:
        if statement.signer_kid in trusted and statement.subject_kid in trusted and valid(statement):
            endorsements.setdefault(statement.subject_kid, []).append(statement)
    return TrustedKeys([row for row in rows if row.kid in trusted], endorsements, withdrawn)


def trusted_key_rows(session: Session, settings: Settings | None = None) -> TrustedKeys:
    """The signing keys this service vouches for: those that chain to the key its store holds."""
    rows = session.scalars(select(SigningKey).order_by(SigningKey.id)).all()
    statements = session.scalars(select(KeyEndorsement).order_by(KeyEndorsement.id)).all()
    withdrawals = session.scalars(select(KeyWithdrawal).order_by(KeyWithdrawal.kid)).all()
    return chain_of_trust(rows, statements, withdrawals, store_kid(settings or get_settings()))


def key_event_count(session: Session) -> int:
    """Key events so far: keys recorded, retired, endorsed, withdrawn (each table only grows)."""
    counts = [
        session.scalar(select(func.count()).select_from(SigningKey)),
        session.scalar(select(func.count(SigningKey.retired_at))),
        session.scalar(select(func.count()).select_from(KeyEndorsement)),
        session.scalar(select(func.count()).select_from(KeyWithdrawal)),
    ]
    return sum(int(count or 0) for count in counts)


def _endorse(session: Session, signer: Signer, subject_kid: str, subject_x: str, relation: Relation) -> None:
    at = int(utcnow().timestamp())
    signature = signer.sign(endorsement_text(relation, signer.kid, subject_kid, subject_x, at))
    session.add(
        KeyEndorsement(
            signer_kid=signer.kid,
            subject_kid=subject_kid,
            relation=relation,
            at=at,
            signature=b64url(signature),
        )
    )


def _grandfather(session: Session, signer: Signer) -> None:
    """The key in force vouches (as predecessors) for the keys on record when endorsements began that no
    key has vouched for yet: once, on its first start after the migration (flushed)."""
    vouched = select(KeyEndorsement.subject_kid).where(KeyEndorsement.relation == "predecessor")
    pending = session.scalars(
        select(SigningKey)
        .join(KeyGrandfathered, KeyGrandfathered.kid == SigningKey.kid)
        .where(SigningKey.kid != signer.kid, SigningKey.kid.not_in(vouched))
    ).all()
    if not pending:
        return
    try:
        with session.begin_nested():
            for row in pending:
                _endorse(session, signer, row.kid, _x(row), "predecessor")
    except IntegrityError:
        pass  # another process vouched for them at the same moment


def _record(session: Session, signer: Signer) -> None:
    """Record the signer's public key as the active one and retire every other (flushed)."""
    _retire_others(session, signer.kid)
    row = SigningKey(kid=signer.kid, public_jwk=signer.public_jwk(), source=signer.source, active=True)
    try:
        with session.begin_nested():
            session.add(row)
    except IntegrityError:
        pass  # another process recorded it at the same moment


def current_signer(session: Session, settings: Settings) -> Signer:
    """The key that signs now, from the store the settings name; recorded (public half) if new."""
    store = key_store(settings)
    signer = store.current()
    _remember(store, signer.kid)
    row = session.scalar(select(SigningKey).where(SigningKey.kid == signer.kid))
    if row is None:
        _record(session, signer)
    elif not row.active:
        raise KeyUnavailable(
            f"the signing key held in {store.describe()} ({signer.kid}) was retired on "
            f"{row.retired_at:%Y-%m-%d} and never signs again; rotate to a new key "
            "(`trikecert rotate-signing-key`)",
            field="signing_key",
            rule="retired",
        )
    _grandfather(session, signer)
    return signer


def rotate_signing_key(session: Session, settings: Settings) -> SigningKey:
    """Put a new key in force in the store, retire every other key in the table and record the new
    one, the old key naming it its successor and the new key naming the old its predecessor (committed
    before the store destroys the old private key); old public keys stay published."""
    store = key_store(settings)

    def handover(old: Signer | None, new: Signer) -> None:
        _record(session, new)
        session.flush()
        if (
            old is not None
            and old.kid != new.kid
            and session.get(SigningKey, _row_id(session, old.kid)) is not None
        ):
            _endorse(session, old, new.kid, str(new.public_jwk()["x"]), "successor")
            _endorse(session, new, old.kid, str(old.public_jwk()["x"]), "predecessor")
        session.commit()

    signer = store.rotate(handover)
    _remember(store, signer.kid)
    row = session.scalar(select(SigningKey).where(SigningKey.kid == signer.kid))
    assert row is not None
    return row


def _row_id(session: Session, kid: str) -> int:
    return int(session.scalar(select(SigningKey.id).where(SigningKey.kid == kid)) or 0)


def endorse_signing_key(session: Session, settings: Settings, kid: str) -> SigningKey:
    """The key in force vouches for an earlier key as its predecessor: after the key was changed outside
    `rotate-signing-key` (a configured key replaced, a token swapped), no statement links them. Commits."""
    signer = current_signer(session, settings)
    row = session.scalar(select(SigningKey).where(SigningKey.kid == kid))
    if row is None:
        raise NotFound(f"kid: no signing key {kid} is on record", field="kid", rule="exists")
    if kid == signer.kid:
        raise Conflict(
            f"kid: {kid} is the key in force; it needs no endorsement", field="kid", rule="in_force"
        )
    _endorse(session, signer, kid, _x(row), "predecessor")
    try:
        session.commit()
    except IntegrityError as error:
        session.rollback()
        raise Conflict(
            f"kid: the key in force already vouches for {kid}", field="kid", rule="endorsed"
        ) from error
    return row


def withdraw_signing_key(
    session: Session, settings: Settings, kid: str, *, reason: str, by: str
) -> SigningKey:
    """Withdraw a key that may be in other hands: the key in force signs the withdrawal (it cannot
    withdraw itself: rotate first). Its papers stop counting online and show "Cannot confirm" offline."""
    reason = reason.strip()
    if not reason:
        raise InvalidInput("reason: say why the key is withdrawn", field="reason", rule="required")
    signer = current_signer(session, settings)
    row = session.scalar(select(SigningKey).where(SigningKey.kid == kid))
    if row is None:
        raise NotFound(f"kid: no signing key {kid} is on record", field="kid", rule="exists")
    if kid == signer.kid:
        raise Conflict(
            f"kid: {kid} is the key in force; rotate first (trikecert rotate-signing-key), then withdraw it",
            field="kid",
            rule="in_force",
        )
    if kid not in {trusted.kid for trusted in trusted_key_rows(session, settings).rows}:
        raise Conflict(f"kid: {kid} is not one of this service's keys", field="kid", rule="untrusted")
    if session.get(KeyWithdrawal, kid) is not None:
        raise Conflict(f"kid: {kid} is already withdrawn", field="kid", rule="withdrawn")
    at = int(utcnow().timestamp())
    signature = b64url(signer.sign(withdrawal_text(kid, _x(row), at)))
    session.add(
        KeyWithdrawal(
            kid=kid, signer_kid=signer.kid, at=at, reason=reason, withdrawn_by=by[:200], signature=signature
        )
    )
    session.commit()
    return row


COSE_OKP, COSE_ED25519 = 1, 6  # COSE key type OKP and curve Ed25519 (RFC 9053)


def cose_key(jwk: dict[str, Any], kid: str) -> str:
    """A public key as a COSE_Key {kty: OKP, kid, alg: EdDSA, crv: Ed25519, x}: CBOR in base64url."""
    x = base64.urlsafe_b64decode(jwk["x"] + "=" * (-len(jwk["x"]) % 4))
    key = {1: COSE_OKP, 2: kid_bytes(kid), 3: EDDSA, -1: COSE_ED25519, -2: x}
    return base64.urlsafe_b64encode(cbor2.dumps(key)).rstrip(b"=").decode()


_published: dict[tuple[object, ...], dict[str, Any]] = {}


def key_event_marks() -> list[ScalarSelect[Any]]:
    """What changes with every key event, as look-ups over the small key tables (to select at once)."""
    return [
        select(func.count()).select_from(SigningKey).scalar_subquery(),
        select(func.count(SigningKey.retired_at)).scalar_subquery(),
        select(func.max(SigningKey.created_at)).scalar_subquery(),
        select(func.count()).select_from(KeyEndorsement).scalar_subquery(),
        select(func.count()).select_from(KeyWithdrawal).scalar_subquery(),
    ]


def _key_marker(session: Session) -> tuple[object, ...]:
    """What changes with every key event, in one statement."""
    return tuple(session.execute(select(*key_event_marks())).one())


def published_keys(session: Session, settings: Settings) -> dict[str, Any]:
    """Every key this service vouches for (those that chain to the key its store holds), newest first,
    as a JWKS with the issuer's name and each COSE_Key; a withdrawn key is listed with its status.
    Kept per process while no key event happened (every /verify asks for it): one statement then."""
    place = (settings.database_url, settings.issuing_authority, store_kid(settings))
    marker = _key_marker(session)
    kept = _published.get(place)
    if kept is not None and kept["marker"] == marker:
        return dict(kept["keys"])
    keys = _published_keys(session, settings)
    _published[place] = {"marker": marker, "keys": keys}
    return dict(keys)


def forget_published_keys() -> None:
    """Drop the key sets kept in memory (tests, which empty and refill one database)."""
    _published.clear()


def _published_keys(session: Session, settings: Settings) -> dict[str, Any]:
    trusted = trusted_key_rows(session, settings)
    return {
        "issuer": settings.issuing_authority,
        "keys": [
            {
                **row.public_jwk,
                "kid": row.kid,
                "alg": ALGORITHM,
                "use": "sig",
                "active": row.active and row.kid not in trusted.withdrawn,
                "status": "compromised"
                if row.kid in trusted.withdrawn
                else ("active" if row.active else "retired"),
                "created_at": row.created_at.isoformat(),
                "cose_key": cose_key(row.public_jwk, row.kid),
            }
            for row in reversed(trusted.rows)
        ],
    }
