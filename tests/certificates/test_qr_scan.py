"""The printed QR code scans: version 10 or lower at level M, modules of 0.75 mm or more, read by zbarimg
from a 72 dpi rendering of the PDF and from a worn print (blurred, noisy, turned, JPEG 30)."""

from __future__ import annotations

import math
import shutil
import subprocess
from datetime import date
from pathlib import Path
from typing import Any

import pypdfium2  # type: ignore[import-untyped]
import pytest
import segno
import zxingcpp
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from PIL import Image

from app.trust.jws import sign_jws
from app.trust.keys import kid_of, okp_key
from app.trust.signing import Claims, legacy_qr_url, verify_input

TOOLS = ("zbarimg", "pdftoppm", "convert")
pytestmark = pytest.mark.skipif(
    any(shutil.which(tool) is None for tool in TOOLS),
    reason="needs zbar-tools, poppler-utils and imagemagick (Debian packages)",
)
ALPHANUMERIC = set("0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ $%*+-./:")
HIGH_DPI = 300


def run(*command: str) -> str:
    done = subprocess.run(command, capture_output=True, text=True, check=False, timeout=120)
    assert done.returncode == 0, (command, done.stderr)
    return done.stdout


def pdf_file(api: TestClient, body: dict[str, Any], folder: Path) -> Path:
    response = api.get(f"/api/v1/certificates/{body['number']}/pdf")
    assert response.status_code == 200
    path = folder / "certificate.pdf"
    path.write_bytes(response.content)
    return path


def page_png(pdf: Path, dpi: int) -> Path:
    stem = pdf.with_name(f"page-{dpi}")
    run("pdftoppm", "-r", str(dpi), "-png", "-singlefile", str(pdf), str(stem))
    return stem.with_suffix(".png")


SEEDS = (1, 2, 3)  # ImageMagick's noise is random; fixed seeds make the wear the same on every run


def worn(png: Path, seed: int) -> Path:
    """A cheap print left in the sun: blurred 1.5 px, speckled, turned 7 degrees, saved as JPEG 30."""
    target = png.with_name(f"worn-{seed}.jpg")
    run(
        "convert",
        str(png),
        "-seed", str(seed),
        "-colorspace", "Gray",
        "-blur", "0x1.5",  # the same Gaussian, in two one-dimensional passes (a third of the time)
        "-attenuate", "0.6", "+noise", "Gaussian",
        "-background", "white", "-rotate", "7",
        "-quality", "30",
        str(target),
    )  # fmt: skip
    return target


def zbar(image: Path) -> list[str]:
    """Every QR code zbarimg reads from the image, as text."""
    done = subprocess.run(
        ["zbarimg", "--quiet", "--raw", "-Sdisable", "-Sqrcode.enable", str(image)],
        capture_output=True,
        check=False,
        timeout=120,
    )
    assert done.returncode in (0, 4), done.stderr  # 4: nothing found
    return [line for line in done.stdout.decode().splitlines() if line]


@pytest.fixture(params=["refusal", "certificate"])
def printed(request: pytest.FixtureRequest, api: TestClient, tmp_path: Path) -> tuple[dict[str, Any], Path]:
    if request.param == "refusal":
        body = study_certificate(api)
    else:
        register(api, FRONT_HEAVY)
        body = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    return body, pdf_file(api, body, tmp_path)


def test_the_qr_code_is_version_10_or_lower_at_level_m_with_modules_of_at_least_0_75_mm(
    printed: tuple[dict[str, Any], Path],
) -> None:
    body, pdf = printed
    document = pypdfium2.PdfDocument(str(pdf))
    try:
        image: Image.Image = document[0].render(scale=HIGH_DPI / 72).to_pil()
    finally:
        document.close()
    (found,) = zxingcpp.read_barcodes(image, formats=zxingcpp.BarcodeFormats(zxingcpp.BarcodeFormat.QRCode))
    assert found.text == body["qr_url"]
    assert set(found.text) <= ALPHANUMERIC  # the whole URL in the QR code's alphanumeric mode
    extra: Any = found.extra
    version = int(extra["Version"])
    assert version <= 10
    assert extra["ECLevel"] in ("M", "Q", "H")
    corners = found.position
    side_px = math.dist((corners.top_left.x, corners.top_left.y), (corners.top_right.x, corners.top_right.y))
    module_mm = side_px / HIGH_DPI * 25.4 / (17 + 4 * version)
    assert module_mm >= 0.75


def test_zbarimg_reads_the_qr_code_from_a_72_dpi_rendering(
    api: TestClient, printed: tuple[dict[str, Any], Path]
) -> None:
    body, pdf = printed
    assert zbar(page_png(pdf, 72)) == [body["qr_url"]]
    keys = api.get("/.well-known/trikecert-keys.json").json()
    assert verify_input(body["qr_url"], keys).claims.number == body["number"]


def test_zbarimg_reads_the_qr_code_from_a_worn_print(printed: tuple[dict[str, Any], Path]) -> None:
    body, pdf = printed
    page = page_png(pdf, 150)
    for seed in SEEDS:
        assert zbar(worn(page, seed)) == [body["qr_url"]], seed


def test_the_same_wear_defeats_the_qr_code_as_it_was_printed_before(api: TestClient, tmp_path: Path) -> None:
    """The earlier JWS URL (version 14) in 42 mm, as the PDF drew it, is unreadable once worn."""
    body = study_certificate(api)
    keys = api.get("/.well-known/trikecert-keys.json").json()
    signer = okp_key(Ed25519PrivateKey.generate())
    claims = Claims(body["number"], "BDG 252 QH", date(2026, 12, 1), date(2027, 12, 1), "NC", 1)
    token = sign_jws(claims, kid=kid_of(signer), key=signer)
    old_url = legacy_qr_url("http://127.0.0.1:8000", body["number"], token)
    old = segno.make(old_url, error="m", boost_error=False)
    assert old.version == 14
    picture = tmp_path / "old.png"
    old.save(str(picture), kind="png", scale=10, border=2)
    side = round(42 / 25.4 * 150)  # 42 mm at 150 dpi: 0.54 mm, 3.2 px a module
    page = Image.new("L", (side + 200, side + 200), 255)
    page.paste(Image.open(picture).convert("L").resize((side, side), Image.Resampling.LANCZOS), (100, 100))
    page.save(picture)
    assert zbar(picture) == [old_url]  # readable before the wear
    for seed in SEEDS:
        assert zbar(worn(picture, seed)) == []
    assert verify_input(body["qr_url"], keys).kid == body["key_id"]
