"""A refusal's PDF lists what would make the vehicle comply, in the pages' one wording; a certificate does
not; the remedies are frozen in the snapshot, and older snapshots without them still read."""

from __future__ import annotations

import subprocess

from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session
from web.test_layout_words import TADPOLE

from app.certificates.facts import Facts
from app.certificates.models import Certificate

STUDY_REMEDIES = (
    "What would make it comply: Carry no more than the driver; or fit more than 54.64 kg of ballast 0.30 m "
    "behind the front wheel; or move the rear bench 0.262 m forward, which still leaves the empty vehicle "
    "non-compliant; or fit rear tyres at least 1.226 times as stiff in cornering as the front."
)


def pdftotext(pdf: bytes) -> str:
    """The PDF's text as poppler reads it, words joined by single spaces."""
    text = subprocess.run(["pdftotext", "-", "-"], input=pdf, capture_output=True, check=True).stdout.decode()
    return " ".join(text.split())


def pdf_of(api: TestClient, number: str) -> bytes:
    response = api.get(f"/api/v1/certificates/{number}/pdf")
    assert response.status_code == 200
    content: bytes = response.content
    return content


def test_the_study_refusal_lists_the_remedies_in_one_paragraph(api: TestClient) -> None:
    body = study_certificate(api)
    text = pdftotext(pdf_of(api, body["number"]))
    assert STUDY_REMEDIES in text
    assert text.count("What would make it comply") == 1


def test_a_certificate_has_no_remedies(api: TestClient) -> None:
    register(api, FRONT_HEAVY)
    body = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    assert "What would make it comply" not in pdftotext(pdf_of(api, body["number"]))


def test_the_remedies_are_kept_in_the_snapshot_and_old_snapshots_read(
    api: TestClient, session: Session
) -> None:
    body = study_certificate(api)
    stored = session.scalars(select(Certificate).where(Certificate.number == body["number"])).one()
    assert stored.facts["remedies"]["ballast_kg"] == "54.64"
    assert stored.facts["remedies"]["seat_shift_unfixable"] == [0]
    facts = Facts.from_json(stored.facts)
    assert facts.remedies_sentence is not None
    assert f"What would make it comply: {facts.remedies_sentence}" == STUDY_REMEDIES
    older = {key: value for key, value in stored.facts.items() if key != "remedies"}
    assert Facts.from_json(older).remedies is None


def test_a_tadpole_s_refusal_prints_its_remedies_from_the_front_axle(api: TestClient) -> None:
    register(api, TADPOLE)
    inspection = weigh(api, "TDP 101 EV", {"left_front_kg": 186, "right_front_kg": 182, "rear_kg": 112})
    refusal = api.post(f"/api/v1/inspections/{inspection}/certificate")
    assert refusal.status_code == 201, refusal.text
    paper = pdftotext(pdf_of(api, refusal.json()["number"]))
    assert (
        "What would make it comply: Carry no more than the driver and one passenger; or fit more than"
        in paper
    )
    assert "kg of ballast 0.30 m behind the front axle" in paper
    assert "front wheel;" not in paper
