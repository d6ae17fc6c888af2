"""Named examples of the public JSON verification for the OpenAPI schema: one per status, and a QR check."""

from __future__ import annotations

from typing import Any

_BASE: dict[str, Any] = {
    "number": "TRK-2026-000001-E",
    "kind": "certificate",
    "registration_number": "KTU 417 XA",
    "max_compliant_occupants": 3,
    "issued_on": "2026-12-03",
    "valid_until": "2027-12-03",
}
_REFUSAL: dict[str, Any] = {
    **_BASE,
    "number": "TRK-2026-000002-U",
    "kind": "refusal",
    "registration_number": "BDG 252 QH",
    "max_compliant_occupants": 1,
}


def _example(summary: str, value: dict[str, Any]) -> dict[str, Any]:
    return {"summary": summary, "value": value}


VERIFICATION_EXAMPLES: dict[str, dict[str, Any]] = {
    "certified": _example(
        "A certificate in force: the driver and up to 2 passengers",
        {**_BASE, "status": "certified", "in_force": True},
    ),
    "refused": _example(
        "A refusal in force: NOT certified; the driver alone at most",
        {**_REFUSAL, "status": "refused", "in_force": False},
    ),
    "revoked": _example(
        "A revoked certificate: it certifies nothing",
        {
            **_BASE,
            "status": "revoked",
            "in_force": False,
            "revoked_on": "2026-12-10",
            "reason": "Wrong wheel readings",
        },
    ),
    "superseded": _example(
        "A certificate replaced by a newer document",
        {
            **_BASE,
            "status": "superseded",
            "in_force": False,
            "superseded_by": "TRK-2026-000003-H",
            "superseded_on": "2027-03-01",
        },
    ),
    "expired": _example(
        "A certificate past its last day",
        {
            **_BASE,
            "issued_on": "2025-12-03",
            "valid_until": "2026-12-03",
            "status": "expired",
            "in_force": False,
        },
    ),
    "qr_genuine": _example(
        "With ?p=: the scanned QR code is genuine for this record",
        {
            **_BASE,
            "status": "certified",
            "in_force": True,
            "qr": "genuine",
            "qr_reason": "ok",
            "qr_reason_text": "the signature checks out (key 3q2-7wAAAAAAAAAA)",
        },
    ),
    "qr_not_genuine": _example(
        "With ?p=: the scanned QR code was altered",
        {
            **_BASE,
            "status": "certified",
            "in_force": True,
            "qr": "not_genuine",
            "qr_reason": "bad_signature",
            "qr_reason_text": "bad signature: the content or the signature was altered, "
            "or it was not signed by us",
        },
    ),
}
