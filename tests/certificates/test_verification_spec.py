"""A third party's verifier, written from docs/verification.md alone with generic libraries (base45,
cbor2, cryptography): it imports nothing of the service. It checks a certificate's and a refusal's
QR codes fetched from the running service (through the TestClient), refuses a tampered payload, and
computes check letters the service agrees with."""

from __future__ import annotations

import base64
import hashlib
import json
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any
from urllib.parse import quote, unquote
from zoneinfo import ZoneInfo

import base45  # type: ignore[import-untyped]
import cbor2
import pytest
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey
from fastapi.testclient import TestClient
from study_data import STUDY_READINGS, STUDY_VEHICLE

# ---- the verifier, section by section of docs/verification.md -----------------------------------

ALPHABET = "ABCDEFGHJKLMNPRSTUVWXYZ"  # section 5
KINDS = {1: "certificate", 2: "refusal"}  # section 3, claim 5
ZONE = ZoneInfo("Africa/Lagos")  # section 3: the service's time zone unless configured otherwise


class NotGenuine(Exception):
    """The code is not a genuine paper of the issuer."""


@dataclass(frozen=True)
class Paper:
    """What a genuine code says."""

    number: str
    registration: str
    compliant: bool
    occupants_with_driver: int
    kind: str | None
    issuer: str | None
    issued_on: str
    valid_until: str
    expires: datetime


def b64url_decode(text: str) -> bytes:
    return base64.urlsafe_b64decode(text + "=" * (-len(text) % 4))


def b64url(raw: bytes) -> str:
    return base64.urlsafe_b64encode(raw).rstrip(b"=").decode()


def check_letter(digits: str) -> str:
    """Section 5: weights 1..10, the letter brings the sum to 0 modulo 23."""
    total = sum(weight * int(digit) for weight, digit in enumerate(digits, start=1))
    return ALPHABET[-total % 23]


def printed_number(ten_digits: int) -> str:
    digits = f"{ten_digits:010d}"
    return f"TRK-{digits[:4]}-{digits[4:]}-{check_letter(digits)}"


def thumbprint_kid(jwk: dict[str, Any]) -> str:
    """Section 4: the first 16 characters of the RFC 7638 thumbprint."""
    canonical = json.dumps({"crv": jwk["crv"], "kty": jwk["kty"], "x": jwk["x"]}, separators=(",", ":"))
    return b64url(hashlib.sha256(canonical.encode()).digest())[:16]


def payload_of_url(url: str) -> str:
    """Section 1: the part after /V/, percent-decoded once."""
    marker = max(url.find("/V/"), url.find("/v/"))
    assert marker >= 0, url
    return unquote(url[marker + 3 :])


def base_of_url(url: str) -> str:
    """Section 6, step 5: what the QR URL holds between '://' and '/V/', to compare with the issuer."""
    marker = max(url.find("/V/"), url.find("/v/"))
    return url[url.index("://") + 3 : marker]


def verify(text: str, key_set: dict[str, Any]) -> Paper:
    """Sections 2 to 4: base45, no zlib, COSE_Sign1, Ed25519 over Sig_structure, then the claims."""
    try:
        raw = base45.b45decode(text.upper())
        sign1 = cbor2.loads(raw)
    except (ValueError, cbor2.CBORDecodeError) as error:
        raise NotGenuine(f"not base45 CBOR: {error}") from error
    if not (isinstance(sign1, cbor2.CBORTag) and sign1.tag == 18 and len(sign1.value) == 4):
        raise NotGenuine("not a COSE_Sign1")
    protected, unprotected, payload, signature = sign1.value
    header = cbor2.loads(protected)
    if header != {1: -8, 4: header.get(4)} or unprotected != {} or len(header[4]) != 12:
        raise NotGenuine(f"unexpected headers {header!r} {unprotected!r}")
    kid = b64url(header[4])
    keys = [key for key in key_set["keys"] if key["kid"] == kid and thumbprint_kid(key) == kid]
    if not keys:
        raise NotGenuine(f"unknown key {kid}")
    public = Ed25519PublicKey.from_public_bytes(b64url_decode(keys[0]["x"]))
    try:
        public.verify(signature, cbor2.dumps(["Signature1", protected, b"", payload]))
    except InvalidSignature as error:
        raise NotGenuine("bad signature") from error
    claims = cbor2.loads(payload)
    ours = claims[-65537]
    issued = datetime.fromtimestamp(claims[6], UTC)
    expires = datetime.fromtimestamp(claims[4], UTC)
    kind = KINDS.get(ours[5]) if 5 in ours else None
    if 5 in ours and kind != ("certificate" if ours[3] else "refusal"):
        raise NotGenuine("the kind and the verdict disagree")
    return Paper(
        number=printed_number(ours[1]),
        registration=ours[2],
        compliant=ours[3],
        occupants_with_driver=ours[4],
        kind=kind,
        issuer=claims.get(1),
        issued_on=issued.astimezone(ZONE).date().isoformat(),
        valid_until=expires.astimezone(ZONE).date().isoformat(),
        expires=expires,
    )


# ---- the service, reached over HTTP only ------------------------------------------------------------

FRONT_HEAVY: dict[str, Any] = {
    "registration_number": "KTU-417-XA",
    "make": "TVS",
    "model": "King",
    "model_year": 2021,
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
}
FRONT_HEAVY_READINGS = {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80}


def issue(api: TestClient, vehicle: dict[str, Any], readings: dict[str, Any]) -> dict[str, Any]:
    assert api.post("/api/v1/vehicles", json=vehicle).status_code == 201
    weighed = api.post(
        "/api/v1/inspections",
        json={"registration_number": vehicle["registration_number"], "readings": readings},
    )
    assert weighed.status_code == 201, weighed.text
    issued = api.post(f"/api/v1/inspections/{weighed.json()['id']}/certificate")
    assert issued.status_code == 201, issued.text
    body: dict[str, Any] = issued.json()
    return body


@pytest.fixture
def papers(api: TestClient) -> dict[str, str]:
    """The QR URLs of a certificate and a refusal, as printed on their papers."""
    certificate = issue(api, FRONT_HEAVY, FRONT_HEAVY_READINGS)
    refusal = issue(api, STUDY_VEHICLE, STUDY_READINGS)
    api.headers.pop("Authorization")  # from here on, what anyone can do
    return {"certificate": certificate["qr_url"], "refusal": refusal["qr_url"]}


def online(client: TestClient, number: str) -> dict[str, Any]:
    answer = client.get(f"/api/v1/verify/{number}")
    assert answer.status_code == 200
    body: dict[str, Any] = answer.json()
    return body


def test_a_certificate_verifies_from_the_specification_alone(
    papers: dict[str, str], client: TestClient
) -> None:
    key_set = client.get("/.well-known/trikecert-keys.json").json()
    paper = verify(payload_of_url(papers["certificate"]), key_set)
    assert (paper.kind, paper.compliant, paper.registration) == ("certificate", True, "KTU 417 XA")
    assert paper.occupants_with_driver == 2  # the driver and one passenger: the driver included
    assert paper.issuer == "127.0.0.1:8000"
    assert paper.issuer.lower() == base_of_url(papers["certificate"]).lower()  # the QR URL's own host
    assert client.get(f"http://{paper.issuer}/.well-known/trikecert-keys.json").json() == key_set
    facts = online(client, paper.number)
    assert (facts["status"], facts["in_force"], facts["kind"]) == ("certified", True, "certificate")
    assert facts["max_compliant_occupants"] == paper.occupants_with_driver
    assert (facts["issued_on"], facts["valid_until"]) == (paper.issued_on, paper.valid_until)
    assert paper.expires > datetime.now(UTC)


def test_a_refusal_is_genuine_and_never_certified(papers: dict[str, str], client: TestClient) -> None:
    key_set = client.get("/.well-known/trikecert-keys.json").json()
    paper = verify(payload_of_url(papers["refusal"]), key_set)
    assert (paper.kind, paper.compliant, paper.registration) == ("refusal", False, "BDG 252 QH")
    assert paper.occupants_with_driver == 1  # the driver alone: no passengers
    facts = online(client, paper.number)
    assert (facts["status"], facts["in_force"], facts["kind"]) == ("refused", False, "refusal")


def test_a_tampered_payload_is_not_genuine(papers: dict[str, str], client: TestClient) -> None:
    key_set = client.get("/.well-known/trikecert-keys.json").json()
    text = payload_of_url(papers["refusal"])
    sign1 = cbor2.loads(base45.b45decode(text))
    protected, unprotected, payload, signature = sign1.value
    claims = cbor2.loads(payload)
    claims[-65537][3] = True  # a refusal passed off as a certificate
    claims[-65537][5] = 1  # certificate
    forged = cbor2.dumps(cbor2.CBORTag(18, [protected, unprotected, cbor2.dumps(claims), signature]))
    with pytest.raises(NotGenuine, match="bad signature"):
        verify(base45.b45encode(forged).decode(), key_set)
    flipped = bytearray(base45.b45decode(text))
    flipped[-1] ^= 1  # one bit of the signature
    with pytest.raises(NotGenuine, match="bad signature"):
        verify(base45.b45encode(bytes(flipped)).decode(), key_set)
    stranger = {"keys": [{**key, "x": b64url(bytes(32))} for key in key_set["keys"]]}
    with pytest.raises(NotGenuine, match="unknown key"):  # the kid no longer matches the key
        verify(text, stranger)
    number = verify(text, key_set).number
    escaped = quote(base45.b45encode(forged).decode(), safe="")  # a space is %20, a '+' is %2B
    answer = client.get(f"/api/v1/verify/{number}?p={escaped}")
    assert (answer.json()["qr"], answer.json()["qr_reason"]) == ("not_genuine", "bad_signature")


def test_the_check_letter_and_the_key_ids_are_computed_as_the_service_computes_them(
    papers: dict[str, str], client: TestClient
) -> None:
    key_set = client.get("/.well-known/trikecert-keys.json").json()
    for key in key_set["keys"]:
        assert thumbprint_kid(key) == key["kid"]
        cose = cbor2.loads(b64url_decode(key["cose_key"]))
        assert cose == {1: 1, 2: b64url_decode(key["kid"]), 3: -8, -1: 6, -2: b64url_decode(key["x"])}
    assert printed_number(2026000001) == "TRK-2026-000001-E"  # the worked example
    assert printed_number(2026000002) == "TRK-2026-000002-U"
    number = verify(payload_of_url(papers["certificate"]), key_set).number
    assert online(client, number)["number"] == number
    letter = number[-1]
    for wrong in (ch for ch in ALPHABET if ch != letter):
        answer = client.get(f"/api/v1/verify/{number[:-1]}{wrong}")
        assert answer.status_code == 404
        assert answer.json()["errors"][0]["rule"] == "check_letter"
