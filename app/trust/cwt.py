"""The QR payload: a CWT (RFC 8392) in a COSE_Sign1 (RFC 9052) signed with Ed25519, in base45 (RFC 9285).

As the EU Digital COVID Certificate does, so the payload fits a QR code's alphanumeric mode:

    COSE_Sign1 = #6.18([ protected: bstr .cbor {1: -8 (EdDSA), 4: kid}, unprotected: {},
                         payload: bstr .cbor CWT claims, signature: bstr (64 bytes) ])
    CWT claims = {1 (iss): base URL without its scheme, 4 (exp): NumericDate, 6 (iat): NumericDate,
                  -65537 (private use): {1: year * 10**6 + sequence, 2: registration,
                                         3: compliant (bool), 4: max occupants, driver counted,
                                         5: kind (1 certificate, 2 refusal)}}

Payloads signed before the issuer and the kind were added (2026-12) have neither `1 (iss)` nor
`5`; they keep verifying, and a payload is either wholly of one layout or refused. The kid is the
published JWK `kid` (16 base64url characters) decoded to its 12 bytes. The certificate number
travels as its ten digits; the check letter is recomputed. No zlib step (the DCC has one): the
64-byte signature is most of the 160 bytes, and it does not compress. The issuer leaves out the
scheme and the kind is a number, because every byte widens the QR code: with a base URL of 30
characters the code stays at version 10. docs/verification.md is the specification a third party
verifies from.

Built by hand with cbor2 and cryptography rather than with `pycose` or `cwt`: one structure with
one algorithm is thirty lines, and the verifier must be strict in ways a general library is not
(exactly these header fields, canonical CBOR with nothing after it, so that no two texts verify as
the same payload). Pure: no database.
"""

from __future__ import annotations

import base64
import binascii
from collections.abc import Mapping
from datetime import UTC, datetime
from typing import Any

import base45  # type: ignore[import-untyped]
import cbor2
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey

from app.trust.claims import Claims, DocumentKind, PayloadRefused, Verified, tampered, usable_key
from app.trust.numbers import SEQUENCE_DIGITS, CertificateNumber, InvalidNumber, parse_number
from app.trust.signer import SignsBytes
from app.trust.validity import local_date
from app.wording import verdict_mark

COSE_SIGN1_TAG = 18
EDDSA = -8  # COSE algorithm EdDSA; with an OKP Ed25519 key it is Ed25519
HEADER_ALG, HEADER_KID = 1, 4
CLAIM_ISS, CLAIM_EXP, CLAIM_IAT = 1, 4, 6
CLAIM_TRIKECERT = -65537  # the first private-use claim key (RFC 8392, section 9.1)
NUMBER, REGISTRATION, COMPLIANT, MAX_OCCUPANTS, KIND = 1, 2, 3, 4, 5
# The two layouts a payload may have: since 2026-12 with the issuer and the kind, and before.
CLAIM_KEYS = frozenset({CLAIM_ISS, CLAIM_EXP, CLAIM_IAT, CLAIM_TRIKECERT})
OURS_KEYS = frozenset({NUMBER, REGISTRATION, COMPLIANT, MAX_OCCUPANTS, KIND})
EARLIER_CLAIM_KEYS = CLAIM_KEYS - {CLAIM_ISS}
EARLIER_OURS_KEYS = OURS_KEYS - {KIND}
MAX_ISSUER = 200
KIND_CODES: dict[DocumentKind, int] = {"certificate": 1, "refusal": 2}
KID_BYTES = 12
BASE45_ALPHABET = frozenset("0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ $%*+-./:")


def kid_bytes(kid: str) -> bytes:
    """The COSE kid of a published key id: its base64url text decoded (16 characters, 12 bytes)."""
    raw = base64.urlsafe_b64decode(kid + "=" * (-len(kid) % 4))
    if len(raw) != KID_BYTES or _b64(raw) != kid:
        raise ValueError(f"key id {kid!r} is not 16 base64url characters")
    return raw


def _b64(raw: bytes) -> str:
    return base64.urlsafe_b64encode(raw).rstrip(b"=").decode()


def _numeric_date(moment: datetime | None) -> int:
    if moment is None:
        raise ValueError("a CWT needs the exact issue and expiry moments")
    return int(moment.timestamp())


def _sig_structure(protected: bytes, payload: bytes) -> bytes:
    return cbor2.dumps(["Signature1", protected, b"", payload])


def sign_cwt(claims: Claims, *, kid: str, key: SignsBytes) -> str:
    """The base45 text of the signed COSE_Sign1 CWT of these claims (needs `issued_at`, `expires_at`)."""
    number = parse_number(claims.number)
    protected = cbor2.dumps({HEADER_ALG: EDDSA, HEADER_KID: kid_bytes(kid)})
    if not claims.issuer:
        raise ValueError("a CWT needs its issuer (the service's base URL without its scheme)")
    payload = cbor2.dumps(
        {
            CLAIM_ISS: claims.issuer,
            CLAIM_EXP: _numeric_date(claims.expires_at),
            CLAIM_IAT: _numeric_date(claims.issued_at),
            CLAIM_TRIKECERT: {
                NUMBER: int(number.digits),
                REGISTRATION: claims.registration,
                COMPLIANT: claims.verdict == "C",
                MAX_OCCUPANTS: claims.max_occupants,
                KIND: KIND_CODES[kind_of(claims.verdict == "C")],
            },
        }
    )
    signature = key.sign(_sig_structure(protected, payload))
    signed = cbor2.dumps(cbor2.CBORTag(COSE_SIGN1_TAG, [protected, {}, payload, signature]))
    text: bytes = base45.b45encode(signed)
    return text.decode("ascii")


def _strict_cbor(raw: bytes, part: str) -> Any:
    """Decode CBOR that is canonical and complete: re-encoding gives back exactly these bytes."""
    try:
        value = cbor2.loads(raw)
        canonical = cbor2.dumps(value) == raw
    except (cbor2.CBORError, ValueError, TypeError, OverflowError, RecursionError) as error:
        raise PayloadRefused("malformed", f"malformed payload: the {part} is not CBOR") from error
    if not canonical:
        raise PayloadRefused("malformed", f"malformed payload: the {part} is not in its shortest CBOR form")
    return value


def _unpack(text: str) -> tuple[bytes, bytes, bytes]:
    """The protected header, payload and signature bytes of a base45 COSE_Sign1."""
    text = text.strip("\r\n\t").upper()  # not spaces (base45 has them); a camera may lower-case
    if not text or not set(text) <= BASE45_ALPHABET:
        raise PayloadRefused("malformed", "malformed payload: expected base45 text (RFC 9285)")
    try:
        raw: bytes = base45.b45decode(text)
    except ValueError as error:
        raise PayloadRefused("malformed", "malformed payload: not valid base45 (RFC 9285)") from error
    sign1 = _strict_cbor(raw, "COSE structure")
    if not (
        isinstance(sign1, cbor2.CBORTag)
        and sign1.tag == COSE_SIGN1_TAG
        and isinstance(sign1.value, list | tuple)  # cbor2 gives a tagged array as a tuple
        and len(sign1.value) == 4
    ):
        raise PayloadRefused("malformed", "malformed payload: expected a COSE_Sign1 (CBOR tag 18)")
    protected, unprotected, payload, signature = sign1.value
    if not (isinstance(protected, bytes) and isinstance(payload, bytes) and isinstance(signature, bytes)):
        raise PayloadRefused("malformed", "malformed payload: COSE_Sign1 parts must be byte strings")
    if not isinstance(unprotected, Mapping) or len(unprotected) != 0:
        raise PayloadRefused("malformed", "malformed payload: the unprotected header must be empty")
    return protected, payload, signature


def _key_id(protected: bytes) -> str:
    header = _strict_cbor(protected, "protected header")
    if not isinstance(header, dict) or set(header) != {HEADER_ALG, HEADER_KID}:
        raise PayloadRefused("malformed", "malformed payload: the header must hold exactly alg and kid")
    if header[HEADER_ALG] != EDDSA:
        raise PayloadRefused(
            "unsupported_algorithm", f"unsupported algorithm {header[HEADER_ALG]!r}; expected EdDSA (-8)"
        )
    kid = header[HEADER_KID]
    if not isinstance(kid, bytes) or len(kid) != KID_BYTES:
        raise PayloadRefused("unknown_key", "unknown key: the key id is not one of ours")
    return _b64(kid)


def _public_key(jwk: dict[str, Any]) -> Ed25519PublicKey:
    x = str(jwk.get("x", ""))
    return Ed25519PublicKey.from_public_bytes(base64.urlsafe_b64decode(x + "=" * (-len(x) % 4)))


def verify_cwt(text: str, jwks: dict[str, Any]) -> Verified:
    """Check a base45 COSE_Sign1 CWT against the published keys; PayloadRefused says why it is not genuine."""
    protected, payload, signature = _unpack(text)
    kid = _key_id(protected)
    public = usable_key(jwks, kid)
    try:
        _public_key(public).verify(signature, _sig_structure(protected, payload))
    except (InvalidSignature, ValueError, binascii.Error) as error:
        raise PayloadRefused(
            "bad_signature",
            "bad signature: the content or the signature was altered, or it was not signed by us",
        ) from error
    return Verified(claims=_claims_of(payload), kid=kid, format="cwt")


def unverified_number(text: str) -> str | None:
    """The certificate number a payload claims, before any check (to show the record beside a forgery)."""
    try:
        _protected, payload, _signature = _unpack(text)
        return _claims_of(payload).number
    except PayloadRefused:
        return None


def _claims_of(payload: bytes) -> Claims:
    try:
        body = _strict_cbor(payload, "claims")
    except PayloadRefused as refused:
        raise tampered(ValueError(refused.message)) from refused
    try:
        current = isinstance(body, dict) and set(body) == CLAIM_KEYS
        if not isinstance(body, dict) or not (current or set(body) == EARLIER_CLAIM_KEYS):
            raise ValueError("expected exactly the claims iss, exp, iat and the trikecert claim")
        ours = body[CLAIM_TRIKECERT]
        if not isinstance(ours, dict) or set(ours) != (OURS_KEYS if current else EARLIER_OURS_KEYS):
            raise ValueError(
                "the trikecert claim must hold number, registration, verdict, occupancy and kind"
            )
        issuer = body.get(CLAIM_ISS)
        if current and (not isinstance(issuer, str) or not 0 < len(issuer) <= MAX_ISSUER):
            raise ValueError("the issuer must be text")
        issued_at, expires_at = _moment(body[CLAIM_IAT]), _moment(body[CLAIM_EXP])
        digits = ours[NUMBER]
        if isinstance(digits, bool) or not isinstance(digits, int) or not 0 <= digits < 10**10:
            raise ValueError("the number must be its ten digits")
        number = CertificateNumber(digits // 10**SEQUENCE_DIGITS, digits % 10**SEQUENCE_DIGITS)
        registration, compliant, occupants = ours[REGISTRATION], ours[COMPLIANT], ours[MAX_OCCUPANTS]
        if not isinstance(registration, str) or not registration:
            raise ValueError("the registration must be text")
        if not isinstance(compliant, bool):
            raise ValueError("the verdict must be true or false")
        if isinstance(occupants, bool) or not isinstance(occupants, int) or not 0 <= occupants < 100:
            raise ValueError("max occupancy must be a whole number")
        kind = kind_of(compliant) if current else None
        if current and ours[KIND] != KIND_CODES[kind_of(compliant)]:
            raise ValueError("the kind must be 1 (certificate) for a compliant verdict, else 2 (refusal)")
    except (ValueError, InvalidNumber, OverflowError, OSError) as error:
        raise tampered(error) from error
    return Claims(
        number=str(number),
        registration=registration,
        issued=local_date(issued_at),
        expires=local_date(expires_at),
        verdict=verdict_mark(compliant),
        max_occupants=occupants,
        issued_at=issued_at,
        expires_at=expires_at,
        issuer=issuer,
        kind=kind,
    )


def kind_of(compliant: bool) -> DocumentKind:
    """The document's kind by its verdict: 'certificate' when compliant, else 'refusal'."""
    return "certificate" if compliant else "refusal"


def _moment(value: Any) -> datetime:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 2**35:
        raise ValueError("a date must be a NumericDate (whole seconds since 1970)")
    return datetime.fromtimestamp(value, UTC)


def read_key_id(text: str) -> str:
    """The key id of a base45 COSE_Sign1 read strictly, before any key is looked up; PayloadRefused
    (malformed, unsupported_algorithm, unknown_key) when the structure cannot be read."""
    protected, _payload, _signature = _unpack(text)
    return _key_id(protected)
