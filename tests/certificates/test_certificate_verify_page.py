"""The public page /verify: anyone, without signing in or JavaScript, sees a certificate's status."""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Any

import pytest
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, study_certificate, weigh
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.certificates.actors import Actor
from app.certificates.service import issue_certificate
from app.config import get_settings
from app.db import utcnow
from app.trust.numbers import CertificateNumber
from app.web.formatting import long_date


@pytest.fixture
def issued(api: TestClient) -> dict[str, Any]:
    body = study_certificate(api)
    api.headers.pop("Authorization")  # the page is public
    return body


def test_a_refusal_in_force_says_not_certified_in_red_with_the_vehicle_and_table_4(
    issued: dict[str, Any], client: TestClient
) -> None:
    page = client.get(f"/verify/{issued['number']}")
    assert page.status_code == 200
    html = page.text
    assert '<div class="status status--refused" id="status"' in html
    assert '<h1 class="status__headline" id="headline">NOT CERTIFIED: refusal</h1>' in html
    assert "VALID" not in html
    assert '<span id="registration">BDG 252 QH</span>' in html
    assert "Bajaj" in html
    assert '<p class="status__occupancy" id="occupancy">This vehicle must not carry passengers</p>' in html
    assert "Certificate" not in html.split('id="status"', 1)[1].split("</div>", 1)[0]
    assert "Not compliant. Laterally stable with the driver alone" in html
    assert "Weight on rear wheels (kg)" in html
    assert "0.696" in html
    assert "+0.009" in html
    assert "<script" not in html
    assert page.headers["cache-control"] == "no-store"


def test_the_qr_url_shows_whether_its_signature_checks_out(
    issued: dict[str, Any], client: TestClient
) -> None:
    assert issued["qr_url"].startswith("HTTP://127.0.0.1:8000/V/")
    genuine = client.get(issued["qr_url"].removeprefix("HTTP://127.0.0.1:8000"))
    assert genuine.url.path == f"/verify/{issued['number']}"
    # Issue 21: the study's paper is a refusal, so a genuine code on it is red, never green.
    assert '<div class="qr-check qr-check--refused" id="qr-check" data-genuine="true">' in genuine.text
    assert (
        '<p class="qr-check__title">The QR code is genuine, but this paper is a REFUSAL</p>' in genuine.text
    )
    assert "qr-check--genuine" not in genuine.text
    technical = genuine.text.split('<div class="details__text">', 1)[1]
    assert technical.startswith(f"<p>Signed with key <code>{issued['key_id']}</code>.</p>")
    assert issued["key_id"] not in genuine.text.split("<details>", 1)[0]
    token = issued["qr_payload"]
    forged = token[:40] + ("A" if token[40] != "A" else "B") + token[41:]
    page = client.get(f"/verify/{issued['number']}", params={"p": forged})
    assert page.status_code == 200
    assert '<div class="qr-check qr-check--forged" id="qr-check" data-genuine="false">' in page.text
    assert '<p class="qr-check__title">The QR code is NOT genuine: do not rely on this paper</p>' in page.text
    assert "The QR code is genuine" not in page.text
    assert page.text.index('id="qr-check"') < page.text.index('id="status"')


def test_an_unknown_or_mistyped_number_is_a_404_page_under_a_red_banner(
    client: TestClient, engine: object
) -> None:
    """Issue 21: a red banner (a plain heading before), with the words the form and the API give."""
    number = str(CertificateNumber(2026, 777))
    unknown = client.get(f"/verify/{number}")
    assert unknown.status_code == 404
    assert '<div class="status status--unknown" id="status" data-status="exists">' in unknown.text
    assert 'id="headline">NOT VALID: no certificate has this number</h1>' in unknown.text
    api = client.get(f"/api/v1/verify/{number}").json()["detail"].removeprefix("number: ")
    assert f'id="number-problem">{api[0].upper()}{api[1:]}.</p>' in unknown.text
    mistyped = client.get("/verify/TRK-2026-000002-A")
    assert mistyped.status_code == 404
    assert 'id="headline">NOT VALID: the number is mistyped</h1>' in mistyped.text
    form = client.get("/verify", params={"number": "TRK-2026-000002-A"})
    api = client.get("/api/v1/verify/TRK-2026-000002-A").json()["detail"].removeprefix("number: ")
    message = f"{api}.".replace("'", "&#39;")  # as Jinja escapes the quotes
    assert api.endswith("has a wrong check letter: a character is mistyped or two are swapped")
    assert f'id="number-problem">{message}</p>' in mistyped.text
    assert f'<li><a href="#number">{message}</a></li>' in form.text
    nonsense = client.get("/verify/nonsense")
    assert nonsense.status_code == 404
    assert 'id="headline">NOT VALID: this is not a certificate number</h1>' in nonsense.text
    assert "status--valid" not in unknown.text + mistyped.text + nonsense.text


def test_the_form_takes_a_number_and_explains_a_mistyped_one(
    issued: dict[str, Any], client: TestClient
) -> None:
    form = client.get("/verify")
    assert form.status_code == 200
    assert '<label class="label " for="number">Certificate number</label>' in form.text
    found = client.get("/verify", params={"number": issued["number"].lower()}, follow_redirects=False)
    assert found.status_code == 303
    assert found.headers["location"] == f"/verify/{issued['number']}"
    wrong = issued["number"][:-1] + ("A" if not issued["number"].endswith("A") else "B")
    refused = client.get("/verify", params={"number": wrong})
    assert refused.status_code == 422
    assert "There is a problem" in refused.text
    assert 'href="#number"' in refused.text
    assert f'value="{wrong}"' in refused.text


def test_a_superseded_certificate_links_to_its_replacement(api: TestClient) -> None:
    register(api, FRONT_HEAVY)
    old = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    new = certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
    page = api.get(f"/verify/{old['number']}")
    replaced_on = long_date(datetime.fromisoformat(new["issued_at"]))
    assert f'id="headline">SUPERSEDED on {replaced_on}</h1>' in page.text
    assert 'class="status status--lapsed"' in page.text
    assert f'<a href="/verify/{new["number"]}" id="newer">Certificate {new["number"]}</a>' in page.text
    fresh = api.get(f"/verify/{new['number']}").text
    assert '<div class="status status--valid" id="status"' in fresh
    assert 'id="headline">VALID CERTIFICATE</h1>' in fresh
    assert 'id="occupancy">Certified for the driver and up to one passenger</p>' in fresh
    valid_until = long_date(datetime.fromisoformat(new["expires_at"]))
    assert f"<p>Valid until {valid_until}.</p>" in fresh
    assert f'<dd id="valid-until">{valid_until}</dd>' in fresh


def test_an_expired_certificate_says_expired(api: TestClient, session: Session) -> None:
    register(api)
    inspection_id = weigh(api)
    months_ago = utcnow() - timedelta(days=400)
    issued = issue_certificate(
        session, inspection_id=inspection_id, actor=Actor.of_cli(), settings=get_settings(), now=months_ago
    )
    page = api.get(f"/verify/{issued.certificate.number}")
    expired_on = long_date(issued.certificate.expires_at)
    assert f'id="headline">EXPIRED on {expired_on}</h1>' in page.text
    assert 'class="status status--lapsed"' in page.text
    assert api.get(f"/api/v1/certificates/{issued.certificate.number}").json()["status"] == "expired"
    again = api.post(f"/api/v1/inspections/{inspection_id}/certificate")
    assert again.status_code == 409
    assert again.json()["errors"][0]["rule"] == "expired"
