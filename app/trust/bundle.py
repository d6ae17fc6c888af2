"""The trust bundle: everything an offline checker needs to decide a paper, signed as a JWS (RFC 7515).

    header  {"alg": "EdDSA", "kid": <16 base64url chars>, "typ": "trikecert-trust+jws"}
    payload {"v": 1, "authority", "issuer", "seq", "made_at", "max_age",
             "keys": [{"kid", "x", "status", "from", "until", "numbers", "endorsements"}],
             "revoked": [[ten-digit number, yyyymmdd, "R" | "S"], ...]}

BUNDLE-SPEC.md and docs/verification.md are the contract; this module writes it (`make_payload`,
`sign_bundle`) and reads it strictly (`read_payload`, `open_bundle`). A key endorsement is an Ed25519
signature by one key over `endorsement_text(...)`, naming another key and the relation between them
(the successor it hands over to, or a predecessor it vouches for). Pure: no database; the records are
gathered by app/certificates/trust_bundle.py.
"""

from __future__ import annotations

import base64
import binascii
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey

from app.trust.signer import SignsBytes

VERSION = 1
TYPE = "trikecert-trust+jws"
ALGORITHM = "EdDSA"
KID_CHARS = 16
KeyStatus = Literal["active", "retired", "compromised"]
Relation = Literal["successor", "predecessor"]
Mark = Literal["R", "S"]
KEY_STATUSES: tuple[KeyStatus, ...] = ("active", "retired", "compromised")
RELATIONS: tuple[Relation, ...] = ("successor", "predecessor")
MAX_BUNDLE_CHARS = 64 * 1024 * 1024
MAX_DATE = 2**35
BundleProblem = Literal[
    "bundle_unreadable",
    "bundle_bad_signature",
    "bundle_untrusted_key",
    "bundle_other_issuer",
    "bundle_rollback",
]


class BundleRefused(Exception):
    """A bundle that must not be used (nor replace the one held); `code` is stable, `message` says why."""

    def __init__(self, code: BundleProblem, message: str) -> None:
        super().__init__(message)
        self.code = code
        self.message = message


@dataclass(frozen=True)
class Endorsement:
    """A statement signed by key `by` about the key it is listed under: its `successor` (the key that
    took over from `by`) or its `predecessor` (a key `by` vouches for as one that signed before it)."""

    relation: Relation
    by: str
    at: int
    sig: str


@dataclass(frozen=True)
class BundleKey:
    """One public key as the bundle lists it: its period, status and the numbers it signed."""

    kid: str
    x: str
    status: KeyStatus
    valid_from: int
    until: int | None
    numbers: tuple[int, int | None] | None
    endorsements: tuple[Endorsement, ...] = ()


@dataclass(frozen=True)
class TrustBundle:
    """A bundle's payload, read strictly; `revoked` maps a ten-digit number to (yyyymmdd, R or S)."""

    authority: str
    issuer: str
    seq: int
    made_at: int
    max_age: int
    keys: tuple[BundleKey, ...]
    revoked: Mapping[int, tuple[int, Mark]] = field(default_factory=dict)
    since: int | None = None

    def key(self, kid: str) -> BundleKey | None:
        """The key with this id, or None."""
        return next((key for key in self.keys if key.kid == kid), None)


def b64url(raw: bytes) -> str:
    """Base64url without padding."""
    return base64.urlsafe_b64encode(raw).rstrip(b"=").decode("ascii")


def unb64url(text: str, part: str) -> bytes:
    """Strict base64url: no padding, no stray characters, canonical trailing bits."""
    if not isinstance(text, str) or not text.isascii():
        raise BundleRefused("bundle_unreadable", f"the bundle's {part} is not base64url")
    try:
        raw = base64.urlsafe_b64decode(text + "=" * (-len(text) % 4))
    except (binascii.Error, ValueError) as error:
        raise BundleRefused("bundle_unreadable", f"the bundle's {part} is not base64url") from error
    if b64url(raw) != text:
        raise BundleRefused("bundle_unreadable", f"the bundle's {part} is not canonical base64url")
    return raw


def endorsement_text(relation: Relation, by: str, subject: str, subject_x: str, at: int) -> bytes:
    """The exact ASCII bytes an endorsement signs (docs/verification.md)."""
    return f"trikecert-key-endorsement:1:{relation}:{by}:{subject}:{subject_x}:{at}".encode("ascii")


def endorsement_holds(endorsement: Endorsement, subject: BundleKey | tuple[str, str], signer_x: str) -> bool:
    """True when `signer_x` (the endorsing key) made this signature about the subject key (kid, x)."""
    kid, x = (subject.kid, subject.x) if isinstance(subject, BundleKey) else subject
    message = endorsement_text(endorsement.relation, endorsement.by, kid, x, endorsement.at)
    return verifies(signer_x, unb64url(endorsement.sig, "endorsement signature"), message)


def verifies(x: str, signature: bytes, message: bytes) -> bool:
    """Ed25519: does the public key `x` (base64url) sign `message` with `signature`?"""
    try:
        Ed25519PublicKey.from_public_bytes(unb64url(x, "key")).verify(signature, message)
    except (InvalidSignature, ValueError, BundleRefused):
        return False
    return True


def yyyymmdd(day: Any) -> int:
    """A date as the bundle writes it: 20261203."""
    return int(day.year) * 10000 + int(day.month) * 100 + int(day.day)


def _key_json(key: BundleKey) -> dict[str, Any]:
    return {
        "kid": key.kid,
        "x": key.x,
        "status": key.status,
        "from": key.valid_from,
        "until": key.until,
        "numbers": None if key.numbers is None else list(key.numbers),
        "endorsements": [{"rel": e.relation, "by": e.by, "at": e.at, "sig": e.sig} for e in key.endorsements],
    }


def make_payload(bundle: TrustBundle) -> dict[str, Any]:
    """The payload object of a bundle (revocations sorted by number)."""
    payload: dict[str, Any] = {
        "v": VERSION,
        "authority": bundle.authority,
        "issuer": bundle.issuer,
        "seq": bundle.seq,
        "made_at": bundle.made_at,
        "max_age": bundle.max_age,
        "keys": [_key_json(key) for key in bundle.keys],
        "revoked": [[number, day, mark] for number, (day, mark) in sorted(bundle.revoked.items())],
    }
    if bundle.since is not None:
        payload["since"] = bundle.since
    return payload


def sign_bundle(payload: Mapping[str, Any], *, kid: str, key: SignsBytes) -> str:
    """The JWS compact serialization of the payload, signed with Ed25519 by the key `kid`."""
    header = json.dumps({"alg": ALGORITHM, "kid": kid, "typ": TYPE}, separators=(",", ":"))
    body = json.dumps(payload, separators=(",", ":"), ensure_ascii=True)
    signing_input = f"{b64url(header.encode())}.{b64url(body.encode())}"
    return f"{signing_input}.{b64url(key.sign(signing_input.encode('ascii')))}"


def _whole(value: Any, what: str, *, low: int = 0, high: int = MAX_DATE) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value < high:
        raise BundleRefused("bundle_unreadable", f"the bundle's {what} must be a whole number")
    return value


def _text(value: Any, what: str, *, size: int | None = None) -> str:
    if not isinstance(value, str) or not value or (size is not None and len(value) != size):
        raise BundleRefused("bundle_unreadable", f"the bundle's {what} must be text")
    return value


def _endorsement(value: Any) -> Endorsement:
    if (
        not isinstance(value, dict)
        or set(value) != {"rel", "by", "at", "sig"}
        or value["rel"] not in RELATIONS
    ):
        raise BundleRefused("bundle_unreadable", "an endorsement must hold exactly rel, by, at and sig")
    return Endorsement(
        value["rel"],
        _text(value["by"], "endorsing key", size=KID_CHARS),
        _whole(value["at"], "endorsement time"),
        _text(value["sig"], "endorsement signature"),
    )


def _numbers(value: Any, status: str) -> tuple[int, int | None] | None:
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != 2:
        raise BundleRefused("bundle_unreadable", "a key's numbers must be [first, last]")
    first = _whole(value[0], "first number", high=10**10)
    last = None if value[1] is None and status == "active" else _whole(value[1], "last number", high=10**10)
    if last is not None and last < first:
        raise BundleRefused("bundle_unreadable", "a key's last number comes before its first")
    return first, last


def _key(value: Any) -> BundleKey:
    names = {"kid", "x", "status", "from", "until", "numbers", "endorsements"}
    if not isinstance(value, dict) or set(value) != names:
        raise BundleRefused("bundle_unreadable", f"a key must hold exactly {', '.join(sorted(names))}")
    status = value["status"]
    if status not in KEY_STATUSES:
        raise BundleRefused("bundle_unreadable", f"a key's status must be one of {', '.join(KEY_STATUSES)}")
    until = None if value["until"] is None else _whole(value["until"], "key's until")
    x = _text(value["x"], "key")
    if len(unb64url(x, "key")) != 32:
        raise BundleRefused("bundle_unreadable", "a key must be 32 bytes of Ed25519")
    endorsements = value["endorsements"]
    if not isinstance(endorsements, list):
        raise BundleRefused("bundle_unreadable", "a key's endorsements must be a list")
    return BundleKey(
        kid=_text(value["kid"], "key id", size=KID_CHARS),
        x=x,
        status=status,
        valid_from=_whole(value["from"], "key's from"),
        until=until,
        numbers=_numbers(value["numbers"], status),
        endorsements=tuple(_endorsement(item) for item in endorsements),
    )


def _revoked(value: Any) -> dict[int, tuple[int, Mark]]:
    if not isinstance(value, list):
        raise BundleRefused("bundle_unreadable", "the revoked list must be a list")
    revoked: dict[int, tuple[int, Mark]] = {}
    previous = -1
    for entry in value:
        if not isinstance(entry, list) or len(entry) != 3 or entry[2] not in ("R", "S"):
            raise BundleRefused("bundle_unreadable", "a revoked entry must be [number, yyyymmdd, 'R' or 'S']")
        number = _whole(entry[0], "revoked number", high=10**10)
        if number <= previous:
            raise BundleRefused("bundle_unreadable", "the revoked list must be sorted by number, once each")
        previous = number
        revoked[number] = (_whole(entry[1], "revocation date", low=10000101, high=99991232), entry[2])
    return revoked


def read_payload(value: Any) -> TrustBundle:
    """The payload object (JSON-decoded) as a TrustBundle; BundleRefused('bundle_unreadable') if any part
    is not of the exact shape of version 1."""
    names = {"v", "authority", "issuer", "seq", "made_at", "max_age", "keys", "revoked"}
    if not isinstance(value, dict) or not names <= set(value) <= names | {"since"}:
        raise BundleRefused("bundle_unreadable", f"the bundle must hold exactly {', '.join(sorted(names))}")
    if value["v"] != VERSION or isinstance(value["v"], bool):
        raise BundleRefused("bundle_unreadable", f"the bundle's version must be {VERSION}")
    if not isinstance(value["keys"], list) or not value["keys"]:
        raise BundleRefused("bundle_unreadable", "the bundle must list its keys")
    keys = tuple(_key(item) for item in value["keys"])
    if len({key.kid for key in keys}) != len(keys):
        raise BundleRefused("bundle_unreadable", "a key id is listed twice")
    return TrustBundle(
        authority=_text(value["authority"], "authority"),
        issuer=_text(value["issuer"], "issuer"),
        seq=_whole(value["seq"], "seq", high=2**53),
        made_at=_whole(value["made_at"], "made_at"),
        max_age=_whole(value["max_age"], "max_age", low=1),
        keys=keys,
        revoked=_revoked(value["revoked"]),
        since=None if "since" not in value else _whole(value["since"], "since", high=2**53),
    )


@dataclass(frozen=True)
class OpenedBundle:
    """A bundle whose signature checks out, signed by `kid`, with its payload."""

    kid: str
    bundle: TrustBundle


def unpack_bundle(text: str) -> OpenedBundle:
    """Read a JWS bundle and check its signature against its own signing key (listed, active); no trust
    decision yet (see `open_bundle`). BundleRefused says why it cannot be used."""
    text = text.strip() if isinstance(text, str) else ""
    parts = text.split(".")
    if not text or len(text) > MAX_BUNDLE_CHARS or len(parts) != 3 or not all(parts):
        raise BundleRefused("bundle_unreadable", "the bundle is not a JWS (three base64url parts)")
    try:
        header = json.loads(unb64url(parts[0], "header"))
        payload = json.loads(unb64url(parts[1], "payload"))
    except (ValueError, UnicodeDecodeError) as error:
        raise BundleRefused("bundle_unreadable", "the bundle's header or payload is not JSON") from error
    if not isinstance(header, dict) or set(header) != {"alg", "kid", "typ"}:
        raise BundleRefused("bundle_unreadable", "the bundle's header must hold exactly alg, kid and typ")
    if header["alg"] != ALGORITHM or header["typ"] != TYPE:
        raise BundleRefused("bundle_unreadable", f"the bundle must be signed {ALGORITHM}, of type {TYPE}")
    kid = _text(header["kid"], "signing key id", size=KID_CHARS)
    bundle = read_payload(payload)
    key = bundle.key(kid)
    if key is None or key.status != "active":
        raise BundleRefused(
            "bundle_bad_signature", f"the bundle is signed by key {kid}, which it does not list as active"
        )
    if not verifies(key.x, unb64url(parts[2], "signature"), f"{parts[0]}.{parts[1]}".encode("ascii")):
        raise BundleRefused(
            "bundle_bad_signature",
            "the bundle's signature does not check out: it was altered or not signed by us",
        )
    return OpenedBundle(kid=kid, bundle=bundle)


def chains_from(
    trusted: Mapping[str, str], bundle: TrustBundle, kid: str, distrusted: Sequence[str] = ()
) -> bool:
    """True when the bundle's key `kid` is trusted (kid -> x, the same x) or reached from a trusted key by
    successor endorsements in the bundle, each signed by a key already reached and never `distrusted`."""
    target = bundle.key(kid)
    if target is None or kid in distrusted:
        return False
    if kid in trusted:
        return trusted[kid] == target.x
    reached = {k: x for k, x in trusted.items() if k not in distrusted}
    progress = True
    while kid not in reached and progress:
        progress = False
        for key in bundle.keys:
            if key.kid in reached or key.kid in distrusted:
                continue
            if any(
                e.relation == "successor" and e.by in reached and endorsement_holds(e, key, reached[e.by])
                for e in key.endorsements
            ):
                reached[key.kid] = key.x
                progress = True
    return kid in reached


def open_bundle(text: str, *, trusted: Mapping[str, str], held: TrustBundle | None = None) -> OpenedBundle:
    """A bundle a checker may use in place of the one it holds: its signature checks out, its signing key
    is trusted (`trusted`: kid -> x, the pinned or configured keys) or chained from one by successor
    endorsements, it names the held bundle's issuer and authority, and it is not older (seq) than it."""
    opened = unpack_bundle(text)
    bundle = opened.bundle
    distrusted = [key.kid for key in held.keys if key.status == "compromised"] if held is not None else []
    if not chains_from(trusted, bundle, opened.kid, distrusted):
        raise BundleRefused(
            "bundle_untrusted_key",
            f"the bundle is signed by key {opened.kid}, which no key this checker trusts has handed over to",
        )
    if held is not None:
        if (bundle.issuer, bundle.authority) != (held.issuer, held.authority):
            raise BundleRefused(
                "bundle_other_issuer",
                f"the bundle is from {bundle.authority} ({bundle.issuer}), "
                f"not {held.authority} ({held.issuer})",
            )
        if bundle.seq < held.seq or (bundle.seq == held.seq and bundle.made_at < held.made_at):
            raise BundleRefused(
                "bundle_rollback",
                f"the bundle (number {bundle.seq}) is older than the one held (number {held.seq})",
            )
    return opened
