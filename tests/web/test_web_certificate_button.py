"""From the inspection page an officer issues the refusal, lands on the certificate, downloads its PDF."""

from __future__ import annotations

import re

from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.certificates.models import Certificate
from app.vehicles.models import Vehicle
from web.webtools import STUDY_READINGS, post_form

FORM_URL = "/vehicles/BDG252QH/inspections/new"


def test_an_officer_issues_the_refusal_from_the_inspection_page_and_downloads_its_pdf(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    stored = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS)
    inspection_url = stored.headers["location"]
    page = web.get(inspection_url)
    assert "No certificate has been issued from this inspection yet" in page.text
    assert "Issue the refusal" in page.text

    issued = post_form(web, inspection_url, f"{inspection_url}/certificate", {})
    assert issued.status_code == 303
    number = issued.headers["location"].removeprefix("/certificates/")
    assert re.fullmatch(r"TRK-\d{4}-\d{6}-[A-Z]", number)
    certificate_page = web.get(issued.headers["location"])
    assert certificate_page.status_code == 200
    assert number in certificate_page.text

    pdf = web.get(f"/certificates/{number}/pdf")
    assert pdf.status_code == 200
    assert pdf.headers["content-type"] == "application/pdf"
    assert pdf.content.startswith(b"%PDF")

    again = web.get(inspection_url)
    assert f'href="/certificates/{number}"' in again.text
    assert "refusal, issued" in again.text
    assert "Show the current refusal" in again.text
    session.expire_all()
    assert session.scalar(select(func.count()).select_from(Certificate)) == 1


def test_issuing_without_the_csrf_token_is_refused_and_issues_nothing(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    inspection_url = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS).headers["location"]
    refused = web.post(f"{inspection_url}/certificate", data={}, follow_redirects=False)
    assert refused.status_code == 403
    session.expire_all()
    assert session.scalar(select(func.count()).select_from(Certificate)) == 0


COMPLIANT_READINGS = {
    "front_kg_1": "200",
    "left_rear_kg_1": "80",
    "right_rear_kg_1": "80",
    "overall_kg_1": "360",
}


def test_an_older_inspection_offers_no_button_once_a_newer_one_is_certified_and_says_why(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    older = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS).headers["location"]
    newer = post_form(web, FORM_URL, FORM_URL, COMPLIANT_READINGS).headers["location"]
    issued = post_form(web, newer, f"{newer}/certificate", {})
    number = issued.headers["location"].removeprefix("/certificates/")

    page = web.get(older)
    assert "Issue the refusal" not in page.text
    assert f'action="{older}/certificate"' not in page.text
    newer_id = newer.removeprefix("/inspections/")
    assert (
        f'<p id="not-issuable"><strong>A newer inspection of this vehicle, No. {newer_id}, '
        f"is already certified (certificate {number}): nothing is issued from this older one.</strong></p>"
    ) in page.text
    assert "Show the current certificate" in web.get(newer).text


def test_the_vehicle_page_shows_its_certificate_in_force_and_the_verdict_before_its_particulars(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    assert "No certificate or refusal has been issued for this vehicle." in web.get("/vehicles/BDG252QH").text
    inspection = post_form(web, FORM_URL, FORM_URL, COMPLIANT_READINGS).headers["location"]
    number = post_form(web, inspection, f"{inspection}/certificate", {}).headers["location"].split("/")[-1]

    page = web.get("/vehicles/BDG252QH").text
    current = page.split('<div id="current-document">', 1)[1].split("</div>", 1)[0]
    assert f'<a href="/certificates/{number}">Certificate {number}</a>' in current
    assert "In force</strong> until" in current
    assert page.index('id="current-document"') < page.index('id="verdict"') < page.index("Make and model")
    assert "Not known" not in page
    assert page.count("Not recorded") == 8  # the chassis number and the 7 figures for the estimates
