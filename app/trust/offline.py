"""The offline decision: a scanned or typed text, the trust bundle held and the device's clock give one
code (BUNDLE-SPEC.md), and each code has its words here, in one function.

The /check page (JavaScript) and `trikecert verify --offline` decide by the same steps, in this order:
not_ours / check_online, no_bundle, clock_behind, stale, damaged, unknown_key, compromised,
not_genuine, revoked / superseded, expired, refusal, certified. The payload is read by cwt.py's own
strict parser; nothing of it is re-implemented here. Pure: no database, no clock of its own.

Two readings the spec leaves open, settled here (docs/verification.md says them too):
- bare text is ours when, after leading white space, it begins with "RRQ" (base45 of the bytes
  0xD2 0x84 with which every COSE_Sign1 of ours begins: tag 18, an array of four) in either case.
  So a payment code of digits and capitals is `not_ours`, and a truncated payload is `damaged`.
- a payload of the earlier layout (signed before 2026-12) carries no issuer; it is not compared then
  (the key that signed it is in the bundle, which is the issuer's own).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from datetime import UTC, date, datetime
from typing import Any, Literal, get_args
from urllib.parse import unquote

from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.trust.bundle import BundleProblem, BundleRefused, TrustBundle, read_payload
from app.trust.claims import PayloadRefused
from app.trust.cwt import read_key_id, verify_cwt
from app.trust.jws import looks_like_jws
from app.trust.numbers import parse_number
from app.web.formatting import long_date, to_local
from app.wording import (
    QR_NOT_GENUINE,
    occupancy_sentence,
    status_headline,
    status_meaning,
    status_tone,
)

Code = Literal[
    "not_ours",
    "check_online",
    "no_bundle",
    "clock_behind",
    "stale",
    "damaged",
    "unknown_key",
    "compromised",
    "not_genuine",
    "revoked",
    "superseded",
    "expired",
    "refusal",
    "certified",
]
CODES: tuple[Code, ...] = get_args(Code)
BUNDLE_CODES: tuple[BundleProblem, ...] = (
    "bundle_unreadable",
    "bundle_bad_signature",
    "bundle_untrusted_key",
    "bundle_other_issuer",
    "bundle_rollback",
)
Tone = Literal["valid", "refused", "revoked", "lapsed", "forged", "none"]
CLOCK_SLACK = 300  # seconds a device's clock (or a signer's) may be off before it counts
OURS_PREFIX = "RRQ"  # base45 of 0xD2 0x84: CBOR tag 18 (COSE_Sign1), an array of four
_URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://[^/?#\s]+(?:/[^?#]*)?/[Vv]/(?P<payload>[^?#]+)$")
_LEGACY = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://[^/?#\s]+(?:/[^?#]*)?/verify/[^?#]*\?(?:.*&)?p=", re.I)


@dataclass(frozen=True)
class OfflineVerdict:
    """What the offline check found: the code and, once the payload was read, what the paper says."""

    code: Code
    detail: str = ""  # why, for the command line and the logs (not for the officer's banner)
    number: str | None = None
    registration: str | None = None
    compliant: bool | None = None
    max_occupants: int | None = None
    issued: date | None = None
    expires: date | None = None
    since: int | None = None  # yyyymmdd of a revocation or a supersession
    kid: str | None = None
    list_made_at: int | None = None


@dataclass(frozen=True)
class OfflineWords:
    """A code in words: the banner's headline, its sentence, the verify page's colour ('none': no colour)."""

    headline: str
    sentence: str
    tone: Tone


_CANNOT = N_("CANNOT CONFIRM")
_NO_COLOUR: dict[str, tuple[str, str]] = {
    "not_ours": (
        N_("NOT A CERTIFICATE'S CODE"),
        N_(
            "This QR code is not a certificate's code (it may be a web address or a payment code). "
            "Scan the code printed on the certificate, or type the text under it."
        ),
    ),
    "check_online": (
        N_("CHECK ONLINE"),
        N_("Older paper: check online. Its code can be checked only with a connection."),
    ),
    "no_bundle": (
        _CANNOT,
        N_(
            "Cannot confirm: no list of keys and revocations is held yet. Connect once to fetch it, "
            "then check again."
        ),
    ),
    "clock_behind": (
        _CANNOT,
        N_(
            "Cannot confirm: this device's clock is behind the time the list was made. Set the date and "
            "time right, then check again."
        ),
    ),
    "stale": (
        _CANNOT,
        N_("Cannot confirm: connect to update the list. The list this device holds is too old to rely on."),
    ),
    "damaged": (
        N_("CANNOT READ THE CODE"),
        N_("The code is damaged or incomplete. Scan it again, or type the certificate number online."),
    ),
    "unknown_key": (
        _CANNOT,
        N_(
            "Cannot confirm: this paper was signed with a key the list does not know yet. Connect to "
            "update the list, then check again."
        ),
    ),
    "compromised": (
        _CANNOT,
        N_(
            "Cannot confirm: check online. The key that signed this paper was withdrawn because it may "
            "have been misused."
        ),
    ),
    "bundle_unreadable": (
        N_("LIST NOT USED"),
        N_("The list received could not be read. The list held before is kept."),
    ),
    "bundle_bad_signature": (
        N_("LIST NOT USED"),
        N_("The list received is not signed by the issuing authority. The list held before is kept."),
    ),
    "bundle_untrusted_key": (
        N_("LIST NOT USED"),
        N_(
            "The list received is signed with a key this device has no reason to trust. The list held "
            "before is kept."
        ),
    ),
    "bundle_other_issuer": (
        N_("LIST NOT USED"),
        N_("The list received is from another authority. The list held before is kept."),
    ),
    "bundle_rollback": (
        N_("LIST NOT USED"),
        N_("The list received is older than the one held. The list held before is kept."),
    ),
}
# The verdicts in the verify page's words and colours (app/wording.py): (kind, status, public status).
_VERDICTS: dict[str, tuple[str, str, str]] = {
    "certified": ("compliant", "issued", "certified"),
    "refusal": ("refusal", "issued", "refused"),
    "revoked": ("compliant", "revoked", "revoked"),
    "superseded": ("compliant", "superseded", "superseded"),
    "expired": ("compliant", "expired", "expired"),
}


def offline_words(code: str) -> OfflineWords:
    """Every offline code (and every bundle refusal) in words: headline, sentence and colour."""
    if code in _VERDICTS:
        kind, status, public = _VERDICTS[code]
        meaning = status_meaning(public)
        sentence = f"{meaning[:1].upper()}{meaning[1:]}."
        return OfflineWords(status_headline(kind, status), sentence, status_tone(kind, status))
    if code == "not_genuine":
        return OfflineWords(_("NOT GENUINE"), f"{_(QR_NOT_GENUINE)}.", "forged")
    headline, sentence = _NO_COLOUR[code]
    return OfflineWords(_(headline), _(sentence), "none")


def checked_against(made_at: int) -> str:
    """'Checked against the list of 3 December 2026, 09:40' (the display time zone)."""
    local = to_local(datetime.fromtimestamp(made_at, UTC))
    return _("Checked against the list of %(date)s, %(time)s") % {
        "date": long_date(local.date()),
        "time": f"{local:%H:%M}",
    }


def words_table() -> dict[str, Any]:
    """Every code's words and the occupancy sentences, as data for the /check page (none retyped in JS)."""
    return {
        "codes": {code: vars(offline_words(code)) for code in (*CODES, *BUNDLE_CODES)},
        "occupancy": {
            "certificate": [occupancy_sentence(True, n) for n in range(10)],
            "refusal": [occupancy_sentence(False, n) for n in range(10)],
        },
    }


@dataclass(frozen=True)
class ReadText:
    """The scanned text sorted: a payload of ours to decide, or a code that ends the check at once."""

    payload: str | None
    code: Code | None


def read_text(text: str) -> ReadText:
    """Step 1: a `/V/` URL (any scheme and host; the payload percent-decoded once) or bare base45 text
    beginning with RRQ is a payload; an older `/verify/<number>?p=` URL or a bare JWS is check_online;
    anything else is not_ours."""
    stripped = text.strip() if isinstance(text, str) else ""
    url = _URL.match(stripped)
    if url is not None and "/verify/" not in stripped.lower():
        return ReadText(unquote(url.group("payload")), None)
    if _LEGACY.match(stripped) or looks_like_jws(stripped):
        return ReadText(None, "check_online")
    bare = text.lstrip().rstrip("\r\n\t") if isinstance(text, str) else ""
    if bare[:3].upper() == OURS_PREFIX:
        return ReadText(bare, None)
    return ReadText(None, "not_ours")


def _bundle(bundle_payload: Any) -> TrustBundle | None:
    if isinstance(bundle_payload, TrustBundle):
        return bundle_payload
    if bundle_payload is None:
        return None
    try:
        return read_payload(bundle_payload)
    except BundleRefused:
        return None


def decide(text: str, bundle_payload: Any, now: int) -> OfflineVerdict:
    """The offline decision on `text` with the bundle's payload held (a TrustBundle, its JSON object, or
    None) at the device's time `now` (UTC seconds), in BUNDLE-SPEC.md's order."""
    read = read_text(text)
    if read.code is not None or read.payload is None:
        return OfflineVerdict(read.code or "not_ours")
    bundle = _bundle(bundle_payload)
    if bundle is None or bundle.since is not None:  # an incremental bundle alone is no list
        return OfflineVerdict("no_bundle")
    made = bundle.made_at
    if now < made - CLOCK_SLACK:
        return OfflineVerdict(
            "clock_behind", f"the clock says {now}, the list was made at {made}", list_made_at=made
        )
    if now > made + bundle.max_age:
        return OfflineVerdict("stale", f"the list expired at {made + bundle.max_age}", list_made_at=made)
    try:
        kid = read_key_id(read.payload)
    except PayloadRefused as refused:
        code: Code = "not_genuine"  # an algorithm other than ours, in a structure that reads
        if refused.reason in ("malformed", "unknown_key"):
            code = "damaged" if refused.reason == "malformed" else "unknown_key"
        return OfflineVerdict(code, refused.message, list_made_at=made)
    key = bundle.key(kid)
    if key is None:
        return OfflineVerdict("unknown_key", f"no key {kid} in the list", kid=kid, list_made_at=made)
    if key.status == "compromised":
        return OfflineVerdict("compromised", f"key {kid} was withdrawn", kid=kid, list_made_at=made)
    jwks = {"keys": [{"kty": "OKP", "crv": "Ed25519", "kid": kid, "x": key.x}]}
    try:
        claims = verify_cwt(read.payload, jwks).claims
    except PayloadRefused as refused:
        return OfflineVerdict("not_genuine", refused.message, kid=kid, list_made_at=made)
    digits = int(parse_number(claims.number).digits)
    paper = OfflineVerdict(
        "certified",
        number=claims.number,
        registration=claims.registration,
        compliant=claims.verdict == "C",
        max_occupants=claims.max_occupants,
        issued=claims.issued,
        expires=claims.expires,
        kid=kid,
        list_made_at=made,
    )
    problem = _not_genuine(
        bundle, key.valid_from, key.until, key.numbers, claims.issuer, claims.issued_at, digits
    )
    if problem:
        return _as(paper, "not_genuine", problem)
    if digits in bundle.revoked:
        day, mark = bundle.revoked[digits]
        return _as(paper, "revoked" if mark == "R" else "superseded", f"{mark} on {day}", since=day)
    assert claims.expires_at is not None  # a CWT always signs its exact moments
    if now >= int(claims.expires_at.timestamp()):
        return _as(paper, "expired", f"expired at {int(claims.expires_at.timestamp())}")
    return paper if paper.compliant else _as(paper, "refusal")


def _not_genuine(
    bundle: TrustBundle,
    valid_from: int,
    until: int | None,
    numbers: tuple[int, int | None] | None,
    issuer: str | None,
    issued_at: datetime | None,
    digits: int,
) -> str:
    """Why a genuinely signed payload still cannot be ours (empty when it can): issuer, period, number."""
    if issuer is not None and issuer != bundle.issuer:
        return f"signed for issuer {issuer!r}, not {bundle.issuer!r}"
    iat = int(issued_at.timestamp()) if issued_at is not None else None
    if iat is not None and iat < valid_from - CLOCK_SLACK:
        return f"issued at {iat}, before its key began signing ({valid_from})"
    if iat is not None and until is not None and iat > until:
        return f"issued at {iat}, after its key was retired ({until})"
    if numbers is None:
        return "its key signed no number"
    first, last = numbers
    if digits < first or (last is not None and digits > last):
        return f"number {digits} is outside the numbers its key signed ({first} to {last or 'now'})"
    return ""


def _as(paper: OfflineVerdict, code: Code, detail: str = "", since: int | None = None) -> OfflineVerdict:
    return OfflineVerdict(
        code,
        detail,
        paper.number,
        paper.registration,
        paper.compliant,
        paper.max_occupants,
        paper.issued,
        paper.expires,
        since,
        paper.kid,
        paper.list_made_at,
    )
