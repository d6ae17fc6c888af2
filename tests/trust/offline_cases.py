"""The table of offline cases (BUNDLE-SPEC.md): every row a text scanned or typed, the bundle a checker
holds (its JWS text, "" for none), the device's clock and the code the decision must give.

`offline_cases(api)` issues real papers through the station API on the test database (a certificate,
a refusal, one revoked and one superseded before the sync), takes the served bundle, and crafts the
rest as an attacker or a broken device would: a payload altered or cut short, codes that are not ours,
a bundle past its age or a clock set back, and papers signed by keys that the bundle lists as unknown,
withdrawn for compromise, or retired (a paper issued after the retirement, a number the key never
signed, and one it did sign, which stays green). Crafted bundles are signed by this service's own key
(the one the checker trusts: `trust_anchor()`), so only the row's point differs.

The same rows are run through `decide` and `trikecert verify --offline` (tests/trust/test_offline.py)
and through the /check page (the checker's browser tests).
"""

from __future__ import annotations

import base64
import json
import time
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any

import base45  # type: ignore[import-untyped]
import cbor2
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS, STUDY_VEHICLE

from app.certificates.actors import Actor
from app.certificates.service import reissue_certificate, revoke_certificate
from app.config import get_settings
from app.trust.bundle import sign_bundle
from app.trust.cwt import sign_cwt
from app.trust.keys import key_store
from app.trust.numbers import CertificateNumber
from app.trust.signer import MemorySigner, Signer
from app.trust.signing import Claims, issuer_claim, qr_url
from app.trust.validity import local_date

BUNDLE_PATH = "/.well-known/trikecert-trust"
DAY = 86400
# A front-heavy trike (every loading case complies); three of them, told apart by plate and chassis.
COMPLIANT: dict[str, Any] = {
    "make": "TVS",
    "model": "King",
    "model_year": 2021,
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}, {"role": "passenger", "x_m": 1.6303}],
}
COMPLIANT_READINGS: dict[str, Any] = {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80}
EMV_PAYMENT = "00020101021129370016A000000677010111011300668123456785802NG5913CHUKWU STORES6005LAGOS6304A1B2"


@dataclass(frozen=True)
class Case:
    """One row: name, the text scanned or typed, the bundle held ("" none), the device's clock, the code."""

    name: str
    payload_text: str
    bundle_text: str
    now_unix: int
    expected_code: str

    def row(self) -> tuple[str, str, str, int, str]:
        """As the spec's tuple (name, payload_text, bundle_text, now_unix, expected_code)."""
        return (self.name, self.payload_text, self.bundle_text, self.now_unix, self.expected_code)


def _issue(
    api: TestClient, registration: str, vehicle: dict[str, Any], readings: dict[str, Any]
) -> dict[str, Any]:
    body = {**vehicle, "registration_number": registration}
    if "chassis_number" not in vehicle:
        digits = "".join(char for char in registration if char.isdigit())  # told apart by the plate's digits
        body["chassis_number"] = f"MD6M14PA7L4F{int(digits):05d}"
    assert api.post("/api/v1/vehicles", json=body).status_code == 201
    inspection = api.post(
        "/api/v1/inspections", json={"registration_number": registration, "readings": readings}
    )
    assert inspection.status_code == 201, inspection.text
    issued = api.post(f"/api/v1/inspections/{inspection.json()['id']}/certificate")
    assert issued.status_code == 201, issued.text
    paper: dict[str, Any] = issued.json()
    return paper


def trust_anchor() -> Signer:
    """This service's own signing key (its public half is what a checker pins)."""
    return key_store(get_settings()).current()


def bundle_payload(bundle_text: str) -> dict[str, Any]:
    """The payload of a bundle's JWS, unchecked (to craft another from it)."""
    payload = bundle_text.split(".")[1]
    value: dict[str, Any] = json.loads(base64.urlsafe_b64decode(payload + "=" * (-len(payload) % 4)))
    return value


def resign(payload: dict[str, Any]) -> str:
    """A bundle of this payload signed by this service's own key."""
    signer = trust_anchor()
    return sign_bundle(payload, kid=signer.kid, key=signer)


def _tampered(payload: str) -> str:
    """The same COSE_Sign1 with its signed claims changed (one more occupant allowed), signature kept."""
    tagged = cbor2.loads(base45.b45decode(payload))
    protected, unprotected, claims_bytes, signature = tagged.value
    claims = cbor2.loads(claims_bytes)
    claims[-65537][4] += 1
    forged = cbor2.CBORTag(18, [protected, unprotected, cbor2.dumps(claims), signature])
    text: bytes = base45.b45encode(cbor2.dumps(forged))
    return text.decode("ascii")


def _paper(
    signer: MemorySigner, *, sequence: int, issued_at: datetime, days: int = 365, issuer: str | None = None
) -> str:
    number = CertificateNumber(issued_at.year, sequence)
    expires_at = issued_at + timedelta(days=days)
    claims = Claims(
        number=str(number),
        registration="KTU 500 XA",
        issued=local_date(issued_at),
        expires=local_date(expires_at),
        verdict="C",
        max_occupants=2,
        issued_at=issued_at,
        expires_at=expires_at,
        issuer=issuer or issuer_claim(get_settings().base_url),
    )
    return sign_cwt(claims, kid=signer.kid, key=signer)


def _key_entry(
    signer: MemorySigner, status: str, start: int, until: int | None, numbers: list[int] | None
) -> dict[str, Any]:
    return {
        "kid": signer.kid,
        "x": signer.public_jwk()["x"],
        "status": status,
        "from": start,
        "until": until,
        "numbers": numbers,
        "endorsements": [],
    }


def offline_cases(api: TestClient, session: Session) -> list[Case]:
    """Issue the papers, fetch the bundle and craft every row of the table (see the module's docstring)."""
    certificate = _issue(api, "KTU 417 XA", COMPLIANT, COMPLIANT_READINGS)
    refusal = _issue(api, STUDY_VEHICLE["registration_number"], STUDY_VEHICLE, STUDY_READINGS)
    revoked = _issue(api, "KTU 418 XA", COMPLIANT, COMPLIANT_READINGS)
    replaced = _issue(api, "KTU 419 XA", COMPLIANT, COMPLIANT_READINGS)
    revoke_certificate(session, number=revoked["number"], actor=Actor.of_cli(), reason="plate forged")
    newer = reissue_certificate(
        session, number=replaced["number"], actor=Actor.of_cli(), reason="misprint", settings=get_settings()
    )
    served = api.get(BUNDLE_PATH)
    assert served.status_code == 200, served.text
    bundle = served.text
    payload = bundle_payload(bundle)
    made_at: int = payload["made_at"]
    now = max(int(time.time()), made_at)

    # Keys of our own making, listed in crafted bundles: one retired in the ordinary way, one withdrawn.
    retired, withdrawn, stranger = (MemorySigner(Ed25519PrivateKey.generate(), "file") for _ in range(3))
    began, ended = now - 200 * DAY, now - 30 * DAY
    in_period = datetime.fromtimestamp(now - 100 * DAY, UTC).replace(microsecond=0)
    after_retiring = datetime.fromtimestamp(now - 20 * DAY, UTC).replace(microsecond=0)
    year = in_period.year * 1_000_000
    crafted = {
        **payload,
        "keys": [
            *payload["keys"],
            _key_entry(retired, "retired", began, ended, [year + 1, year + 500]),
            _key_entry(withdrawn, "compromised", began, ended, [year + 501, year + 600]),
        ],
    }
    with_keys = resign(crafted)
    expired_at = datetime.fromtimestamp(now - 150 * DAY, UTC).replace(microsecond=0)

    cut = certificate["qr_payload"][: len(certificate["qr_payload"]) * 2 // 3]
    return [
        Case("certificate (QR URL)", certificate["qr_url"], bundle, now, "certified"),
        Case(
            "certificate (bare text, lower case)", certificate["qr_payload"].lower(), bundle, now, "certified"
        ),
        Case("refusal", refusal["qr_url"], bundle, now, "refusal"),
        Case("revoked before the sync", revoked["qr_url"], bundle, now, "revoked"),
        Case("superseded before the sync", replaced["qr_url"], bundle, now, "superseded"),
        Case(
            "the reissued paper", qr_url(get_settings().base_url, newer.qr_payload), bundle, now, "certified"
        ),
        Case(
            "tampered payload (occupancy raised)",
            _tampered(certificate["qr_payload"]),
            bundle,
            now,
            "not_genuine",
        ),
        Case("truncated payload", cut, bundle, now, "damaged"),
        Case("not ours: a web address", "https://example.com/pay?id=42", bundle, now, "not_ours"),
        Case("not ours: a payment code", EMV_PAYMENT, bundle, now, "not_ours"),
        Case(
            "older paper (JWS in a /verify URL)",
            f"http://127.0.0.1:8000/verify/{certificate['number']}?p=eyJhbGciOiJFZDI1NTE5In0.e30.c2ln",
            bundle,
            now,
            "check_online",
        ),
        Case("no bundle held", certificate["qr_url"], "", now, "no_bundle"),
        Case("stale bundle", certificate["qr_url"], bundle, made_at + payload["max_age"] + 1, "stale"),
        Case("clock set back", certificate["qr_url"], bundle, made_at - 301, "clock_behind"),
        Case(
            "unknown key",
            _paper(stranger, sequence=700, issued_at=in_period),
            with_keys,
            now,
            "unknown_key",
        ),
        Case(
            "key withdrawn for compromise",
            _paper(withdrawn, sequence=550, issued_at=in_period),
            with_keys,
            now,
            "compromised",
        ),
        Case(
            "key retired before the paper's issue time",
            _paper(retired, sequence=100, issued_at=after_retiring),
            with_keys,
            now,
            "not_genuine",
        ),
        Case(
            "number outside the key's range",
            _paper(retired, sequence=900, issued_at=in_period),
            with_keys,
            now,
            "not_genuine",
        ),
        Case(
            "another issuer",
            _paper(retired, sequence=101, issued_at=in_period, issuer="trikecert.elsewhere.example"),
            with_keys,
            now,
            "not_genuine",
        ),
        Case(
            "retired key, paper from its period",
            _paper(retired, sequence=102, issued_at=in_period),
            with_keys,
            now,
            "certified",
        ),
        Case(
            "expired paper",
            _paper(retired, sequence=103, issued_at=expired_at, days=30),
            with_keys,
            now,
            "expired",
        ),
        Case(
            "expired paper, clock set back within the list's age",
            _paper(retired, sequence=104, issued_at=expired_at, days=30),
            with_keys,
            max(made_at - 301, 0),
            "clock_behind",
        ),
        Case(
            "bundle whose signature fails",
            certificate["qr_url"],
            bundle[:-4] + ("AAAA" if not bundle.endswith("AAAA") else "BBBB"),
            now,
            "no_bundle",
        ),
    ]


def case_rows(api: TestClient, session: Session) -> list[tuple[str, str, str, int, str]]:
    """The table as the spec's tuples."""
    return [case.row() for case in offline_cases(api, session)]
