"""One wording of every fact: the same sentence on the pages, in the PDF, in the CLI and in the API.

The occupancy sentence, the verdict sentence, the document's kind, its validity date, the time of
weighing (in the display zone, the zone named) and the loads to 0.01 kg, read back from each channel.
"""

from __future__ import annotations

import io
from datetime import datetime
from typing import Any

import pytest
from certificate_helpers import certify, register, weigh
from fastapi.testclient import TestClient
from pypdf import PdfReader
from sqlalchemy.orm import Session
from study_data import STUDY_READINGS
from web.webtools import OFFICER_EMAIL, PASSWORD, hidden, sign_in

from app.accounts.service import create_user
from app.certificates.actors import Actor
from app.certificates.service import revoke_certificate
from app.cli import main
from app.web.formatting import local_time, long_date
from app.wording import document_headline

REFUSAL_OCCUPANCY = "This vehicle must not carry passengers"
REFUSAL_VERDICT = (
    "Not compliant. Laterally stable with the driver alone; "
    "unstable with the driver and one or more passengers."
)
CERTIFIED_OCCUPANCY = "Certified for the driver and up to 2 passengers"
CERTIFIED_VERDICT = "Compliant. Laterally stable in every loading case, up to the driver and 2 passengers."
FRONT_HEAVY_3: dict[str, Any] = {
    "registration_number": "KTU-417-XA",
    "make": "TVS",
    "model": "King",
    "wheelbase_m": 2.0,
    "seats": [{"role": "driver", "x_m": 0.9303}] + [{"role": "passenger", "x_m": 1.4}] * 2,
}


def pdf_text(api: TestClient, number: str, prefix: str = "/api/v1") -> str:
    response = api.get(f"{prefix}/certificates/{number}/pdf")
    assert response.status_code == 200
    reader = PdfReader(io.BytesIO(response.content))
    return " ".join(" ".join(page.extract_text().split()) for page in reader.pages)


def cli(capsys: pytest.CaptureFixture[str], *args: str, exit_status: int = 0) -> str:
    assert main(list(args)) == exit_status
    out: str = capsys.readouterr().out
    return out


@pytest.mark.parametrize(
    ("vehicle", "readings", "occupancy", "verdict", "until"),
    [
        (None, STUDY_READINGS, REFUSAL_OCCUPANCY, REFUSAL_VERDICT, "This refusal stands until"),
        (
            FRONT_HEAVY_3,
            {"front_kg": 220, "left_rear_kg": 70, "right_rear_kg": 70},
            CERTIFIED_OCCUPANCY,
            CERTIFIED_VERDICT,
            "Valid until",
        ),
    ],
)
def test_the_occupancy_verdict_and_validity_read_the_same_everywhere(
    api: TestClient,
    capsys: pytest.CaptureFixture[str],
    vehicle: dict[str, Any] | None,
    readings: dict[str, Any],
    occupancy: str,
    verdict: str,
    until: str,
) -> None:
    register(api, vehicle) if vehicle else register(api)
    registration = vehicle["registration_number"] if vehicle else "BDG 252 QH"
    body = certify(api, weigh(api, registration, readings))
    valid_until = long_date(datetime.fromisoformat(body["expires_at"]))

    assert (body["max_occupancy"], body["verdict"]) == (occupancy, verdict)

    page = api.get(f"/verify/{body['number']}").text
    assert f'<p class="status__occupancy" id="occupancy">{occupancy}</p>' in page
    assert f'<p class="panel__verdict">{verdict}</p>' in page
    assert f"<p>{until} {valid_until}.</p>" in page

    text = pdf_text(api, body["number"])
    # The paper opens with what it allows (issue 21): a certificate's occupancy as its headline,
    # worded by the same occupancy_limit; a refusal's sentence right under "NOT CERTIFIED: REFUSAL".
    kind = "refusal" if vehicle is None else "compliant"
    opening = document_headline(kind, body["max_compliant_occupants"])
    assert text.startswith(opening if kind == "compliant" else f"{opening} {occupancy} "), text[:200]
    assert verdict in text
    assert f"{'Valid' if until == 'Valid until' else 'Refusal stands'} until {valid_until}." in text
    assert "Certified maximum occupancy" not in text

    # Issue 21: `trikecert verify` exits 3 for a genuine refusal (0 before), 0 only for a certificate.
    out = cli(capsys, "verify", body["qr_url"], exit_status=0 if body["compliant"] else 3)
    assert f"\n{occupancy}\n" in out
    assert f". {'Valid' if until == 'Valid until' else 'This refusal stands'} until {valid_until}.\n" in out


def test_a_refusal_is_called_a_refusal_and_times_name_their_zone(
    api: TestClient, session: Session, capsys: pytest.CaptureFixture[str]
) -> None:
    register(api)
    inspection_id = weigh(api)
    inspection = api.get(f"/api/v1/inspections/{inspection_id}").json()
    weighed = local_time(datetime.fromisoformat(inspection["created_at"]))
    assert weighed.endswith(" WAT")  # the display zone, Africa/Lagos, named
    rear = [case["rear_kg"] for case in inspection["loading_cases"]]
    assert rear[1] == 283.49

    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    shown = api.get(f"/inspections/{inspection_id}").text
    assert f'<strong id="occupancy">{REFUSAL_OCCUPANCY}</strong>' in shown
    assert ">283.49</td>" in shown
    issued = api.post(
        f"/inspections/{inspection_id}/certificate",
        data={"csrf_token": hidden(shown)},
        follow_redirects=False,
    )
    number = issued.headers["location"].rsplit("/", 1)[1]
    landed = api.get(issued.headers["location"]).text
    assert f"<p>Refusal {number} issued.</p>" in landed
    assert "Certificate" not in landed.split('role="status"', 1)[1].split("</div>", 1)[0]
    assert f"{weighed} at Test weighbridge" in landed

    assert cli(capsys, "issue-certificate", str(inspection_id)) == f"Already issued: refusal {number}.\n"
    text = pdf_text(api, number, prefix="")
    assert weighed in text
    assert "283.49" in text
    assert "Lateral Stability Refusal" in text
    assert f"Refusal number {number}" in text
    assert "Certificate number" not in text


def test_a_revoked_refusal_is_called_a_refusal_when_it_is_asked_for_again(
    api: TestClient, session: Session
) -> None:
    register(api)
    inspection_id = weigh(api)
    body = certify(api, inspection_id)
    revoke_certificate(session, number=body["number"], actor=Actor.of_cli(), reason="Ticket forged")
    again = api.post(f"/api/v1/inspections/{inspection_id}/certificate")
    assert again.status_code == 409
    assert f"refusal {body['number']} of this inspection was revoked" in again.json()["errors"][0]["message"]
