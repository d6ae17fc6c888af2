"""Papers that cannot be mistaken (issue 21): what a certificate or a refusal says first, the stamp on
one no longer in force, words a reader understands, every font embedded and the QR code's real size.

The PDFs are read back as a reader gets them: text with poppler's `pdftotext`, fonts with `pdffonts`,
pixels rendered with pdfium. With TRIKECERT_SCREENSHOTS=1 the certificate, the refusal and the
revoked certificate are saved as docs/screenshots/certificate-pdf.png, refusal-pdf.png and
revoked-pdf.png (rendered with `pdftoppm`).
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
from datetime import datetime, timedelta
from decimal import Decimal
from pathlib import Path
from typing import Any

import pypdfium2  # type: ignore[import-untyped]
import pytest
import zxingcpp
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from fastapi.testclient import TestClient
from PIL import Image
from sqlalchemy import select
from sqlalchemy.orm import Session
from web.webtools import OFFICER_EMAIL, PASSWORD, sign_in

import app.certificates.records as records
from app.accounts.service import create_user
from app.certificates.actors import Actor
from app.certificates.facts import CaseFacts
from app.certificates.models import Certificate
from app.certificates.pdf import HEADLINE_PAD, HEADLINE_SIZE, places_for, refusal_reason
from app.certificates.service import revoke_certificate
from app.documents.layout import MARGIN, line_height
from app.web.formatting import long_date

REPO = Path(__file__).resolve().parents[2]
SCREENSHOTS = REPO / "docs" / "screenshots"
MM = 25.4  # mm per inch
REASON = "wrong wheel readings"


def tool(name: str) -> str:
    """The path of a poppler tool, which the PDF tests need."""
    binary = shutil.which(name)
    assert binary, f"poppler-utils ({name}) must be installed for the PDF tests"
    return binary


def page_texts(pdf: bytes) -> list[str]:
    """The text of each page, as pdftotext reads it."""
    done = subprocess.run([tool("pdftotext"), "-", "-"], input=pdf, capture_output=True, check=True)
    return done.stdout.decode("utf-8").split("\f")[:-1]


def first_lines(text: str, count: int) -> list[str]:
    """The first `count` lines of a page that have text."""
    return [line.strip() for line in text.splitlines() if line.strip()][:count]


def fonts_of(pdf: bytes) -> list[tuple[str, str]]:
    """Each font of the PDF as pdffonts lists it: (name, embedded yes/no)."""
    done = subprocess.run([tool("pdffonts"), "-"], input=pdf, capture_output=True, check=True)
    rows = done.stdout.decode("utf-8").splitlines()[2:]
    found = []
    for row in rows:
        fields = row.split()
        # name type... encoding emb sub uni object ID: the last five columns are fixed
        found.append((fields[0], fields[-5]))
    return found


def rendered(pdf: bytes, page: int = 0, dpi: int = 100) -> Image.Image:
    """One page as pixels."""
    document = pypdfium2.PdfDocument(pdf)
    try:
        image: Image.Image = document[page].render(scale=dpi / 72).to_pil().convert("RGB")
    finally:
        document.close()
    return image


def is_red(pixel: Any) -> bool:
    """A strong red, as the refusal's band and frame and the stamp print (an RGB pixel)."""
    r, g, b = pixel
    return bool(r > 140 and g < 60 and b < 60)


def red_share(image: Image.Image) -> float:
    """The share of the page's pixels that are red."""
    colours = image.getcolors(maxcolors=image.width * image.height) or []
    red = sum(count for count, colour in colours if is_red(colour))
    return red / (image.width * image.height)


def at(image: Image.Image, x_mm: float, y_mm: float, dpi: int = 100) -> Any:
    """The RGB pixel at a point given in mm from the page's top left."""
    return image.getpixel((round(x_mm / MM * dpi), round(y_mm / MM * dpi)))


def download(client: TestClient, path: str, **headers: str) -> Any:
    response = client.get(path, headers=headers)
    assert response.status_code == 200, response.text
    return response


def certificate(api: TestClient) -> dict[str, Any]:
    """A compliant trike's certificate: the driver and up to one passenger."""
    register(api, FRONT_HEAVY)
    return certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))


def screenshot(pdf: bytes, name: str) -> None:
    """With TRIKECERT_SCREENSHOTS=1, save page 1 of the PDF as docs/screenshots/<name>.png."""
    if not os.environ.get("TRIKECERT_SCREENSHOTS"):
        return
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    subprocess.run(
        [
            tool("pdftoppm"),
            "-r",
            "110",
            "-png",
            "-singlefile",
            "-f",
            "1",
            "-l",
            "1",
            "-",
            str(SCREENSHOTS / name),
        ],
        input=pdf,
        check=True,
    )


def test_a_certificate_opens_with_the_occupancy_it_certifies(api: TestClient) -> None:
    body = certificate(api)
    pdf = download(api, f"/api/v1/certificates/{body['number']}/pdf").content
    screenshot(pdf, "certificate-pdf")
    [text] = page_texts(pdf)
    assert first_lines(text, 3) == [
        "CERTIFIED: the driver and up to one passenger",
        "Compliant. Laterally stable in every loading case, up to the driver and one passenger.",
        "Tricycle Lateral Stability Certification Authority",
    ]
    flat = " ".join(text.split())
    assert "NOT CERTIFIED" not in flat
    assert "Empty (no occupants) 360.00 160.00 0.444" in flat
    assert "Decided exactly under the rule: LSF below 2/3 in every loading case (rules v1)" in flat
    for internal in ("lsf<2/3", "cumulative-cases", "Status when issued", "ISSUED", "None"):
        assert internal not in flat, internal
    # Black on white: nothing on a certificate is red.
    assert red_share(rendered(pdf)) == 0


def test_a_refusal_opens_in_red_with_not_certified_and_what_the_vehicle_may_carry(api: TestClient) -> None:
    body = study_certificate(api)
    answer = download(api, f"/api/v1/certificates/{body['number']}/pdf")
    assert answer.headers["x-document-status"] == "refused"  # never "issued" or "valid" to a machine
    pdf = answer.content
    screenshot(pdf, "refusal-pdf")
    [text] = page_texts(pdf)
    assert first_lines(text, 3) == [
        "NOT CERTIFIED: REFUSAL",
        "This vehicle must not carry passengers",
        "Tricycle Lateral Stability Certification Authority",
    ]
    lines = [line.strip() for line in text.splitlines()]
    assert "- Empty (no occupants): LSF 0.696 is above the limit 2/3 (0.667) by 0.030." in lines
    assert "- Driver + 2 passengers: LSF 0.697 is above the limit 2/3 (0.667) by 0.031." in lines
    assert not any(re.search(r"\bNone\b", line) for line in lines), text
    assert f"NOT CERTIFIED: Lateral Stability Refusal {body['number']}" in lines  # the foot of every page
    image = rendered(pdf)
    assert is_red(at(image, 20, 17))  # the solid red band behind "NOT CERTIFIED: REFUSAL"
    assert is_red(at(image, 7, 150))  # the red frame round the page
    assert is_red(at(image, 203, 150))
    assert red_share(image) > 0.02


def case(occupants: int, lsf: str, variance: str) -> CaseFacts:
    return CaseFacts(occupants, "", Decimal(500), Decimal(350), Decimal(lsf), Decimal(variance), False, False)


def test_two_lsfs_that_print_alike_never_print_different_margins() -> None:
    # At 3 decimals both print 0.700, above the limit by 0.034 and by 0.033: one decimal more for all.
    empty, two = case(0, "0.70037", "-0.03370"), case(3, "0.69962", "-0.03295")
    assert places_for([empty, two]) == 4
    assert (
        refusal_reason(empty, 4)
        == "Empty (no occupants): LSF 0.7004 is above the limit 2/3 (0.6667) by 0.0337."
    )
    assert (
        refusal_reason(two, 4)
        == "Driver + 2 passengers: LSF 0.6996 is above the limit 2/3 (0.6667) by 0.0330."
    )
    # An LSF just above the limit never prints as the limit itself.
    assert places_for([case(1, "0.66690", "-0.00023")]) == 4
    # The study's figures are apart at 3 decimals: they print as the pages print them.
    assert places_for([case(0, "0.69638", "-0.02971"), case(2, "0.68027", "-0.01361")]) == 3


def test_every_font_of_a_certificate_a_refusal_and_a_stamp_is_embedded(
    api: TestClient, session: Session
) -> None:
    refused = study_certificate(api)
    certified = certificate(api)
    revoke_certificate(session, number=certified["number"], actor=Actor.of_cli(), reason=REASON)
    for number in (refused["number"], certified["number"]):
        pdf = download(api, f"/api/v1/certificates/{number}/pdf").content
        found = fonts_of(pdf)
        assert found, number
        assert all(embedded == "yes" for _name, embedded in found), found
        assert not any("courier" in name.lower() for name, _embedded in found), found


def qr_width_mm(pdf: bytes) -> float:
    """The printed width of the QR code on page 1, measured from its dark modules at 300 dpi."""
    dpi = 300
    image = rendered(pdf, dpi=dpi)
    [found] = zxingcpp.read_barcodes(image, formats=zxingcpp.BarcodeFormats(zxingcpp.BarcodeFormat.QRCode))
    corners = [found.position.top_left, found.position.bottom_right]
    cx = sum(point.x for point in corners) / 2
    cy = sum(point.y for point in corners) / 2
    reach = round(26 / MM * dpi)  # half the code and a little of its quiet zone, never past it
    box = image.crop((round(cx) - reach, round(cy) - reach, round(cx) + reach, round(cy) + reach)).convert(
        "L"
    )
    dark = box.point(lambda value: 255 if value < 128 else 0).getbbox()
    assert dark is not None
    left, _top, right, _bottom = dark
    return (right - left) / dpi * MM


def test_the_qr_code_prints_as_wide_as_the_readme_says(api: TestClient) -> None:
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    [stated] = re.findall(r"printed (\d+(?:\.\d+)?) mm wide", readme)
    for body in (study_certificate(api), certificate(api)):
        width = qr_width_mm(download(api, f"/api/v1/certificates/{body['number']}/pdf").content)
        assert abs(width - float(stated)) < 0.2, (width, stated)


def officer(api: TestClient, session: Session) -> TestClient:
    """The same client, signed in to the pages as an officer instead of a station."""
    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    return api


def stored(session: Session, number: str) -> bytes:
    session.expire_all()
    pdf = session.scalar(select(Certificate.pdf).where(Certificate.number == number))
    assert pdf is not None
    return bytes(pdf)


def assert_stamped(pdf: bytes, original: bytes, sha256: str, headline: str) -> None:
    """The stored original, unchanged at the start of the file, with the stamp first on every page."""
    assert pdf.startswith(original)
    assert hashlib.sha256(original).hexdigest() == sha256
    texts = page_texts(pdf)
    assert len(texts) == len(page_texts(original))
    for text in texts:
        assert " ".join(first_lines(text, 2)[0].split()) == headline, text[:300]
        assert "Not in force: do not rely on this paper." in text
    assert all(embedded == "yes" for _name, embedded in fonts_of(pdf))


def test_a_revoked_certificate_downloads_stamped_from_the_api_and_the_officer_page(
    api: TestClient, session: Session
) -> None:
    body = certificate(api)
    number, sha256 = body["number"], body["pdf_sha256"]
    path = f"/api/v1/certificates/{number}/pdf"
    clean = download(api, path)
    original = clean.content
    assert clean.headers["x-document-status"] == "certified"
    assert clean.headers["etag"] == f'"{sha256}"'
    assert f'filename="{number}.pdf"' in clean.headers["content-disposition"]

    revoke_certificate(session, number=number, actor=Actor.of_cli(), reason=REASON)
    revoked_at = api.get(f"/api/v1/certificates/{number}").json()["revocation"]["revoked_at"]
    headline = f"REVOKED on {long_date(datetime.fromisoformat(revoked_at))}: {REASON}"
    # A copy fetched before the revocation is not current any more: never a 304 for the clean paper.
    answer = download(api, path, **{"If-None-Match": f'"{sha256}"'})
    assert answer.headers["x-document-status"] == "revoked"
    assert answer.headers["x-original-sha256"] == sha256
    assert answer.headers["etag"] != f'"{sha256}"'
    assert f'filename="{number}-REVOKED.pdf"' in answer.headers["content-disposition"]
    assert_stamped(answer.content, original, sha256, headline)
    assert api.get(path, headers={"If-None-Match": answer.headers["etag"]}).status_code == 304
    assert download(api, path).content == answer.content  # generated from the record, the same each time
    screenshot(answer.content, "revoked-pdf")
    # "CERTIFIED: ..." struck through in red: at the middle of the opening line, red where it was black.
    y = MARGIN + HEADLINE_PAD + line_height(HEADLINE_SIZE) * 0.45
    assert not is_red(at(rendered(original), 100, y))
    assert is_red(at(rendered(answer.content), 100, y))

    # The record is as it was: the stored bytes, their hash.
    assert stored(session, number) == original
    assert api.get(f"/api/v1/certificates/{number}").json()["pdf_sha256"] == sha256

    page = download(officer(api, session), f"/certificates/{number}/pdf")
    assert page.content == answer.content
    assert page.headers["x-document-status"] == "revoked"


def test_a_superseded_certificate_downloads_stamped_with_the_newer_number(
    api: TestClient, session: Session
) -> None:
    old = certificate(api)
    original = download(api, f"/api/v1/certificates/{old['number']}/pdf").content
    newer = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    assert newer["supersedes"] == old["number"]
    answer = download(api, f"/api/v1/certificates/{old['number']}/pdf")
    issued = long_date(datetime.fromisoformat(newer["issued_at"]))
    headline = f"SUPERSEDED on {issued} by certificate {newer['number']}"
    assert_stamped(answer.content, original, old["pdf_sha256"], headline)
    assert answer.headers["x-document-status"] == "superseded"
    assert f'filename="{old["number"]}-SUPERSEDED.pdf"' in answer.headers["content-disposition"]
    # The newer one is in force: its paper is the stored one, clean.
    current = download(api, f"/api/v1/certificates/{newer['number']}/pdf")
    assert hashlib.sha256(current.content).hexdigest() == newer["pdf_sha256"]
    assert stored(session, old["number"]) == original


def test_an_expired_refusal_downloads_stamped_expired(
    api: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    body = study_certificate(api)
    original = download(api, f"/api/v1/certificates/{body['number']}/pdf").content
    expires = datetime.fromisoformat(body["expires_at"])
    monkeypatch.setattr(records, "utcnow", lambda: expires + timedelta(days=1))
    answer = download(api, f"/api/v1/certificates/{body['number']}/pdf")
    assert answer.headers["x-document-status"] == "expired"
    assert_stamped(answer.content, original, body["pdf_sha256"], f"EXPIRED on {long_date(expires)}")


def test_a_long_reason_is_cut_to_one_line_of_the_band_and_the_line_under_it_says_where_it_is(
    api: TestClient, session: Session
) -> None:
    body = certificate(api)
    original = download(api, f"/api/v1/certificates/{body['number']}/pdf").content
    reason = "The rear wheels were weighed on an uncalibrated scale " * 12
    revoke_certificate(session, number=body["number"], actor=Actor.of_cli(), reason=reason)
    pdf = download(api, f"/api/v1/certificates/{body['number']}/pdf").content
    [text] = page_texts(pdf)
    band, under, *_rest = first_lines(text, 3)
    assert band.startswith("REVOKED on ")
    assert band.endswith("\u2026")
    assert " ".join(reason.split()).startswith(band.split(": ", 1)[1].removesuffix("\u2026").strip())
    assert (
        under
        == f"Not in force: do not rely on this paper. The record: http://127.0.0.1:8000/verify/{body['number']}"
    )
    assert pdf.startswith(original)
