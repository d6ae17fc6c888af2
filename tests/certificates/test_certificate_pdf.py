"""The PDF reads like Table 4 (real text), and its QR code decodes to a payload that verifies offline."""

from __future__ import annotations

import io
from typing import Any

import pypdfium2  # type: ignore[import-untyped]
import pytest
import zxingcpp
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from fastapi.testclient import TestClient
from PIL import Image
from pypdf import PdfReader

from app.trust.signing import PayloadRefused, verify_input


def pdf_of(api: TestClient, number: str) -> bytes:
    response = api.get(f"/api/v1/certificates/{number}/pdf")
    assert response.status_code == 200
    content: bytes = response.content
    return content


def text_of(pdf: bytes) -> str:
    reader = PdfReader(io.BytesIO(pdf))
    assert len(reader.pages) == 1
    box = reader.pages[0].mediabox
    assert (round(float(box.width) * 25.4 / 72), round(float(box.height) * 25.4 / 72)) == (210, 297)
    return " ".join(reader.pages[0].extract_text().split())


def qr_of(pdf: bytes) -> str:
    document = pypdfium2.PdfDocument(pdf)
    try:
        image: Image.Image = document[0].render(scale=300 / 72).to_pil()
    finally:
        document.close()
    # A phone's scanner looks for QR codes: a search of every format once read a stripe of the page as
    # a second, one-dimensional code (a false find that depends on the run's random key and payload).
    found = zxingcpp.read_barcodes(image, formats=zxingcpp.BarcodeFormats(zxingcpp.BarcodeFormat.QRCode))
    assert len(found) == 1
    assert found[0].format == zxingcpp.BarcodeFormat.QRCode
    return str(found[0].text)


def keys(api: TestClient) -> dict[str, Any]:
    published: dict[str, Any] = api.get("/.well-known/trikecert-keys.json").json()
    return published


@pytest.fixture
def refusal(api: TestClient) -> tuple[dict[str, Any], bytes]:
    body = study_certificate(api)
    return body, pdf_of(api, body["number"])


def test_the_refusal_reads_like_table_4_with_the_verdict_in_words(
    refusal: tuple[dict[str, Any], bytes],
) -> None:
    body, pdf = refusal
    text = text_of(pdf)
    for expected in (
        "Lateral Stability Refusal",
        body["number"],
        "BDG 252 QH",
        "Bajaj",
        "Occupants",
        "Total weight (kg)",
        "Actual LSF",
        "Standard (max)",
        "Variance",
        "Result",
        "Empty (no occupants) 359.00 250.00 0.696 2/3 (0.667) -0.030 NC",
        "Driver 431.00 283.49 0.658 2/3 (0.667) +0.009 C",
        "Driver + 1 passenger 503.00 342.18 0.680 2/3 (0.667) -0.014 NC",
        "Driver + 2 passengers 575.00 400.87 0.697 2/3 (0.667) -0.031 NC",
        "Driver + 3 passengers 647.00 459.56 0.710 2/3 (0.667) -0.044 NC",
        "Not compliant. Laterally stable with the driver alone; "
        "unstable with the driver and one or more passengers.",
        "This vehicle must not carry passengers",
        "Driver + 1 passenger: LSF 0.680 is above the limit 2/3 (0.667) by 0.014.",
        "limit 2/3",
        "Scan to verify, or visit http://127.0.0.1:8000/verify and enter the number",
        "Test weighbridge",
    ):
        assert expected in text, (expected, text)


def test_a_compliant_vehicle_gets_a_certificate(api: TestClient) -> None:
    register(api, FRONT_HEAVY)
    body = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    text = text_of(pdf_of(api, body["number"]))
    assert "Lateral Stability Certificate" in text
    assert "Refusal" not in text
    assert text.startswith("CERTIFIED: the driver and up to one passenger ")
    assert "MD6M14PA7L4F00123" in text
    assert "2021" in text


def test_the_qr_code_decodes_to_the_verify_url_whose_payload_verifies_offline(
    api: TestClient, refusal: tuple[dict[str, Any], bytes]
) -> None:
    body, pdf = refusal
    scanned = qr_of(pdf)
    assert scanned == body["qr_url"]
    verified = verify_input(scanned, keys(api))
    claims = verified.claims
    assert (claims.number, claims.registration, claims.verdict, claims.max_occupants) == (
        body["number"],
        "BDG 252 QH",
        "NC",
        1,
    )
    assert claims.issued.isoformat() < claims.expires.isoformat()
    assert verified.kid == body["key_id"]


def test_flipping_any_one_character_of_the_payload_is_refused(
    api: TestClient, refusal: tuple[dict[str, Any], bytes]
) -> None:
    body, _pdf = refusal
    token: str = body["qr_payload"]
    published = keys(api)
    for index, char in enumerate(token):
        flipped = token[:index] + ("A" if char != "A" else "B") + token[index + 1 :]
        with pytest.raises(PayloadRefused):
            verify_input(flipped, published)
