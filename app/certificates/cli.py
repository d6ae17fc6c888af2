"""The certificate sub-commands of `trikecert`: verify offline, issue, reissue, revoke, keys."""

from __future__ import annotations

import argparse
import json
import sys
import urllib.request
from pathlib import Path
from typing import TYPE_CHECKING, Any

from app.config import get_settings
from app.db import get_sessionmaker
from app.errors import InvalidInput
from app.ids import cli_id

if TYPE_CHECKING:
    from app.certificates.wording import PublicStatus
    from app.trust.bundle import OpenedBundle
    from app.trust.claims import Claims


def load_keys(source: str | None) -> dict[str, Any]:
    """A published key set from a saved file, an http(s) URL, or (None) this service's database."""
    if source is None:
        from app.trust.keys import published_keys

        with get_sessionmaker()() as session:
            return published_keys(session, get_settings())
    if source.startswith(("http://", "https://")):
        with urllib.request.urlopen(source, timeout=10) as answer:  # noqa: S310 (scheme checked above)
            data: Any = json.load(answer)
    else:
        try:
            data = json.loads(Path(source).read_text(encoding="utf-8"))
        except (OSError, ValueError) as error:
            raise InvalidInput(f"--keys: cannot read a key set from {source}: {error}") from error
    if not isinstance(data, dict) or not isinstance(data.get("keys"), list):
        raise InvalidInput(f"--keys: {source} is not a key set (a JSON object with a 'keys' list)")
    return data


NOT_IN_FORCE = 3  # exit status: the code is genuine, but the paper does not certify the vehicle now
CANNOT_DECIDE = 4  # exit status (offline): no verdict either way; the sentence says what to do


def cmd_verify(args: argparse.Namespace) -> int:
    """Check a QR payload or verify URL; print its status as the JSON verification names it.

    Exit 0 only for a genuine certificate in force, 1 when the code is not genuine, 3 when it is
    genuine but the paper certifies nothing now (refused, revoked, superseded or expired). With
    --keys the check is offline and cannot see a revocation or a replacement; without, this
    service's record is read too.
    """
    from app.certificates.records import verify_base
    from app.certificates.wording import in_force, status_meaning, until_sentence
    from app.trust.signing import PayloadRefused, verify_input
    from app.web.formatting import long_date
    from app.wording import document_kind, occupancy_sentence

    if args.offline:
        return verify_offline(args)
    keys = load_keys(args.keys)
    try:
        verified = verify_input(args.payload, keys)
        online = None if args.keys is not None else record_status(args.payload, keys, verified.claims)
    except PayloadRefused as refused:
        print(f"trikecert: NOT GENUINE ({refused.reason}): {refused.message}", file=sys.stderr)
        return 1
    claims = verified.claims
    status, details = online if online is not None else (offline_status(claims), [])
    print(f"GENUINE: signed by key {verified.kid}")
    print(f"status: {status} ({status_meaning(status)})")
    kind_code = "compliant" if claims.verdict == "C" else "refusal"
    kind = document_kind(kind_code)
    print(f"{kind} {claims.number} for {claims.registration}")
    print(occupancy_sentence(claims.verdict == "C", claims.max_occupants))
    print(f"issued {long_date(claims.issued)}. {until_sentence(kind_code, long_date(claims.expires))}")
    if claims.issuer is not None:
        print(f"issuer: {claims.issuer}")
    for line in details:
        print(line)
    if online is None:
        print(
            "offline check: a revocation or a replacement shows online only: "
            f"{verify_base(get_settings())}/{claims.number}"
        )
    return 0 if in_force(status) else NOT_IN_FORCE


def trust_anchors(given: list[str] | None) -> list[str]:
    """The key ids a bundle may be signed by (or chain from): --anchor, then TRIKECERT_TRUST_ANCHORS."""
    kids = list(given or [])
    kids += [kid.strip() for kid in get_settings().trust_anchors.split(",") if kid.strip()]
    return kids


def anchored(text: str, anchors: list[str], held: OpenedBundle | None = None) -> OpenedBundle:
    """Open a bundle trusting the anchor key ids (each checked as the thumbprint of the key the bundle
    lists under it) and the held bundle's own signing key; BundleRefused says why not."""
    from app.trust.bundle import BundleRefused, open_bundle, unpack_bundle
    from app.trust.signer import kid_of_jwk

    listed = unpack_bundle(text).bundle
    trusted: dict[str, str] = {}
    for source in (listed, held.bundle if held is not None else None):
        for key in source.keys if source is not None else ():
            jwk = {"kty": "OKP", "crv": "Ed25519", "x": key.x}
            if key.kid in anchors and kid_of_jwk(jwk) == key.kid:
                trusted[key.kid] = key.x
    if held is not None:
        pinned = held.bundle.key(held.kid)  # the key that signed the bundle held: pinned
        if pinned is not None:
            trusted[pinned.kid] = pinned.x
    if not trusted:
        raise BundleRefused(
            "bundle_untrusted_key",
            "no trust anchor: give --anchor KID (the key id this service publishes) or set "
            "TRIKECERT_TRUST_ANCHORS",
        )
    return open_bundle(text, trusted=trusted, held=held.bundle if held is not None else None)


def verify_offline(args: argparse.Namespace) -> int:
    """`trikecert verify --offline --bundle FILE PAYLOAD`: decide as the /check page does.

    Exit 0 certified, 1 not genuine, 3 genuine but not in force (refusal, revoked, superseded,
    expired), 4 cannot decide (not ours, no usable bundle, clock behind, bundle too old, damaged,
    unknown or withdrawn key): the sentence says what to do.
    """
    import time

    from app.certificates.wording import until_sentence
    from app.trust.bundle import BundleRefused
    from app.trust.offline import checked_against, decide, offline_words
    from app.web.formatting import long_date
    from app.wording import occupancy_sentence

    bundle = None
    if args.bundle is None:
        print(
            "trikecert: --offline needs --bundle FILE (written by `trikecert trust-bundle`)", file=sys.stderr
        )
    else:
        try:
            bundle = anchored(
                Path(args.bundle).read_text(encoding="ascii"), trust_anchors(args.anchor)
            ).bundle
        except (OSError, UnicodeDecodeError) as error:
            print(f"trikecert: cannot read the bundle {args.bundle}: {error}", file=sys.stderr)
        except BundleRefused as refused:
            print(f"trikecert: {offline_words(refused.code).sentence} ({refused.message})", file=sys.stderr)
    now = args.now if args.now is not None else int(time.time())
    verdict = decide(args.payload, bundle, now)
    words = offline_words(verdict.code)
    print(f"{words.headline} ({verdict.code})")
    print(words.sentence)
    if verdict.number is not None:
        print(f"registration: {verdict.registration} (compare with the plate)")
        print(f"number: {verdict.number}")
        if verdict.compliant is not None and verdict.max_occupants is not None:
            print(occupancy_sentence(verdict.compliant, verdict.max_occupants))
        if verdict.issued is not None and verdict.expires is not None:
            kind_code = "compliant" if verdict.compliant else "refusal"
            until = until_sentence(kind_code, long_date(verdict.expires))
            print(f"issued {long_date(verdict.issued)}. {until}")
    if verdict.list_made_at is not None:
        print(checked_against(verdict.list_made_at))
    if verdict.detail:
        print(f"why: {verdict.detail}")
    return {"certified": 0, "not_genuine": 1, "refusal": NOT_IN_FORCE, "revoked": NOT_IN_FORCE}.get(
        verdict.code, NOT_IN_FORCE if verdict.code in ("superseded", "expired") else CANNOT_DECIDE
    )


def cmd_trust_bundle(args: argparse.Namespace) -> int:
    """Write this service's trust bundle to a file, or (--from) take one in for a held file: checked
    against the anchors and the held bundle, and written only when it may replace it."""
    from app.trust.bundle import BundleRefused, unpack_bundle
    from app.trust.offline import offline_words

    out = Path(args.out)
    if args.source is None:
        from app.certificates.trust_bundle import build_bundle

        with get_sessionmaker()() as session:
            built = build_bundle(session, get_settings())
        _write_atomically(out, built.body)
        print(f"wrote the trust bundle (list number {built.state[0]}) to {out}")
        return 0
    held = None
    if out.exists():
        try:
            held = unpack_bundle(out.read_text(encoding="ascii"))
        except (OSError, UnicodeDecodeError, BundleRefused) as error:
            print(
                f"trikecert: the held bundle {out} cannot be read ({error}); it is replaced", file=sys.stderr
            )
    try:
        text = _read_source(args.source)
        opened = anchored(text, trust_anchors(args.anchor), held)
    except BundleRefused as refused:
        print(f"trikecert: {offline_words(refused.code).sentence} ({refused.message})", file=sys.stderr)
        return CANNOT_DECIDE
    except (OSError, UnicodeDecodeError) as error:
        print(f"trikecert: cannot read the bundle from {args.source}: {error}", file=sys.stderr)
        return CANNOT_DECIDE
    _write_atomically(out, text.strip().encode("ascii"))
    print(
        f"took in the trust bundle (list number {opened.bundle.seq}, signed by key {opened.kid}) into {out}"
    )
    return 0


def _read_source(source: str) -> str:
    if source.startswith(("http://", "https://")):
        with urllib.request.urlopen(source, timeout=10) as answer:  # noqa: S310 (scheme checked above)
            raw: bytes = answer.read(64 * 1024 * 1024 + 1)
        return raw.decode("ascii")
    return Path(source).read_text(encoding="ascii")


def _write_atomically(path: Path, data: bytes) -> None:
    """Write beside, then rename over: a reader sees the old bundle or the new one, never half."""
    temporary = path.with_name(f".{path.name}.new")
    temporary.write_bytes(data)
    temporary.replace(path)


def offline_status(claims: Claims) -> PublicStatus:
    """The status the signed claims alone give: certified or refused until the expiry, then expired."""
    from app.certificates.wording import public_status
    from app.db import utcnow
    from app.trust.validity import local_date

    now = utcnow()
    lapsed = now >= claims.expires_at if claims.expires_at is not None else claims.expires < local_date(now)
    return public_status(
        "compliant" if claims.verdict == "C" else "refusal", "expired" if lapsed else "issued"
    )


def record_status(
    payload: str, keys: dict[str, Any], claims: Claims
) -> tuple[PublicStatus, list[str]] | None:
    """The status of the payload's document in this service's database, with the revocation or the
    replacement in words; None when the number is not on record here. PayloadRefused (tampered)
    when the signed claims are not the record's."""
    from app.certificates.records import certificate_status, find_certificate
    from app.certificates.verification import check_payload
    from app.certificates.wording import public_status
    from app.trust.claims import PayloadRefused
    from app.web.formatting import long_date

    with get_sessionmaker()() as session:
        certificate = find_certificate(session, claims.number)
        if certificate is None:
            return None
        checked = check_payload(payload, keys, certificate)
        if not checked.genuine:
            raise PayloadRefused("tampered", checked.message)
        status = public_status(certificate.kind, certificate_status(certificate))
        details = []
        if status == "revoked" and certificate.revocation is not None:
            revocation = certificate.revocation
            details.append(f"revoked on {long_date(revocation.revoked_at)}: {revocation.reason}")
        if status == "superseded" and certificate.superseded_by is not None:
            newer = certificate.superseded_by
            details.append(f"superseded on {long_date(newer.issued_at)} by {newer.number}")
        return status, details


def cmd_issue(args: argparse.Namespace) -> int:
    """Issue the certificate of an inspection as an administrator."""
    from app.certificates.actors import Actor
    from app.certificates.service import issue_certificate
    from app.wording import issued_message

    with get_sessionmaker()() as session:
        issued = issue_certificate(
            session,
            inspection_id=args.inspection_id,
            actor=Actor.of_cli(),
            settings=get_settings(),
            second_language=args.second_language,
        )
        certificate = issued.certificate
        print(issued_message(certificate.kind, certificate.number, issued.created))
    return 0


def cmd_reissue(args: argparse.Namespace) -> int:
    """Reissue a certificate (same inspection and expiry), superseding it."""
    from app.certificates.actors import Actor
    from app.certificates.service import reissue_certificate

    with get_sessionmaker()() as session:
        new = reissue_certificate(
            session, number=args.number, actor=Actor.of_cli(), reason=args.reason, settings=get_settings()
        )
        print(f"reissued as {new.number}; {args.number} is superseded")
    return 0


def cmd_revoke(args: argparse.Namespace) -> int:
    """Revoke a certificate for good, with a reason, recorded as done by cli:<os user>."""
    from app.certificates.actors import Actor
    from app.certificates.service import revoke_certificate
    from app.wording import revoked_message

    with get_sessionmaker()() as session:
        certificate = revoke_certificate(
            session, number=args.number, actor=Actor.of_cli(), reason=args.reason
        )
        print(f"{revoked_message(certificate.kind, certificate.number)} Reason: {args.reason}")
    return 0


def cmd_rotate(_args: argparse.Namespace) -> int:
    """Retire the active signing key and make a new one; old keys stay published."""
    from app.trust.keys import rotate_signing_key

    with get_sessionmaker()() as session:
        key = rotate_signing_key(session, get_settings())
        print(f"new signing key {key.kid}; earlier keys stay published so old certificates still verify")
    return 0


def cmd_withdraw_key(args: argparse.Namespace) -> int:
    """Withdraw a signing key that may be in other hands (signed by the key in force)."""
    from app.certificates.trust_bundle import forget_bundles
    from app.trust.keys import withdraw_signing_key

    with get_sessionmaker()() as session:
        withdraw_signing_key(session, get_settings(), args.kid, reason=args.reason, by=_actor_label())
    forget_bundles()
    print(
        f"withdrew signing key {args.kid}: its papers no longer count as genuine online and show "
        "'Cannot confirm' offline once checkers update their list; reissue the papers it signed"
    )
    return 0


def _actor_label() -> str:
    """Who runs the command, as the audit log names them."""
    from app.certificates.actors import Actor

    return Actor.of_cli().label


def cmd_endorse_key(args: argparse.Namespace) -> int:
    """The key in force vouches for an earlier key (after the key was changed outside rotation)."""
    from app.trust.keys import endorse_signing_key

    with get_sessionmaker()() as session:
        endorse_signing_key(session, get_settings(), args.kid)
    print(f"the key in force now vouches for {args.kid}: its papers count as genuine again")
    return 0


def cmd_keys(args: argparse.Namespace) -> int:
    """Print (or save) the published key set, for offline verification."""
    text = json.dumps(load_keys(None), indent=2)
    if args.output:
        Path(args.output).write_text(text + "\n", encoding="utf-8")
        print(f"saved the published keys to {args.output}")
    else:
        print(text)
    return 0


def add_certificate_commands(commands: Any) -> None:
    """Add the certificate sub-commands to the `trikecert` parser's sub-parsers."""
    verify = commands.add_parser(
        "verify",
        help="check a certificate's QR payload (or verify URL); exit 0 only for a certificate in force, "
        "1 not genuine, 3 genuine but refused, revoked, superseded or expired, 4 (--offline) cannot decide",
    )
    verify.add_argument("payload", metavar="PAYLOAD_OR_URL")
    verify.add_argument(
        "--keys", metavar="FILE_OR_URL", help="published keys (default: this database's keys)"
    )
    verify.add_argument(
        "--offline", action="store_true", help="decide from a trust bundle alone, as the /check page does"
    )
    verify.add_argument("--bundle", metavar="FILE", help="the trust bundle (trikecert trust-bundle --out)")
    verify.add_argument(
        "--anchor",
        metavar="KID",
        action="append",
        help="a key id the bundle must be signed by or chain from (repeatable; also TRIKECERT_TRUST_ANCHORS)",
    )
    verify.add_argument("--now", type=int, metavar="UNIX", help="decide as at this UTC time (tests, audits)")
    verify.set_defaults(handler=cmd_verify)

    issue = commands.add_parser("issue-certificate", help="issue an inspection's certificate (admin)")
    issue.add_argument("inspection_id", type=cli_id)
    issue.add_argument(
        "--second-language",
        choices=("en", "ha", "yo", "ig", "pcm"),
        help="printed under the English (en: English only); default TRIKECERT_PAPER_SECOND_LANGUAGE",
    )
    issue.set_defaults(handler=cmd_issue)

    reissue = commands.add_parser("reissue-certificate", help="reissue a certificate, superseding it (admin)")
    reissue.add_argument("number")
    reissue.add_argument("--reason", required=True)
    reissue.set_defaults(handler=cmd_reissue)

    revoke = commands.add_parser("revoke-certificate", help="revoke a certificate for good (admin)")
    revoke.add_argument("number")
    revoke.add_argument("--reason", required=True)
    revoke.set_defaults(handler=cmd_revoke)

    commands.add_parser(
        "rotate-signing-key", help="make a new signing key; old ones stay published"
    ).set_defaults(handler=cmd_rotate)

    bundle = commands.add_parser(
        "trust-bundle",
        help="write this service's trust bundle to a file; with --from, take one in for a police post "
        "(kept only when it may replace the file held)",
    )
    bundle.add_argument("--out", metavar="FILE", required=True)
    bundle.add_argument("--from", dest="source", metavar="FILE_OR_URL")
    bundle.add_argument("--anchor", metavar="KID", action="append")
    bundle.set_defaults(handler=cmd_trust_bundle)

    withdraw = commands.add_parser(
        "withdraw-signing-key",
        help="withdraw a signing key that may be in other hands (rotate first if it is the key in force)",
    )
    withdraw.add_argument("kid")
    withdraw.add_argument("--reason", required=True)
    withdraw.set_defaults(handler=cmd_withdraw_key)

    endorse = commands.add_parser(
        "endorse-signing-key",
        help="have the key in force vouch for an earlier key (only after changing the key by hand)",
    )
    endorse.add_argument("kid")
    endorse.set_defaults(handler=cmd_endorse_key)

    keys = commands.add_parser("signing-keys", help="print or save the published keys (for offline checks)")
    keys.add_argument("--output", metavar="FILE")
    keys.set_defaults(handler=cmd_keys)
