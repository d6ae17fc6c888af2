"""One wording per kind of fact across the officers' pages: a date as `long_date` says it (in times
too, and in a date box's hint), a gap as "Not recorded", a station named with brackets of its own."""

from __future__ import annotations

from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.accounts.models import User
from app.config import get_settings
from app.inspections.service import InspectionRequest, record_inspection
from app.stations.service import create_station
from app.vehicles.models import Vehicle
from app.web.formatting import local_today, long_date
from web.webtools import ADMIN_EMAIL, sign_in, wheel_readings

STUDY = wheel_readings(108, 115, 135, 359)
WEEKDAYS = ("Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday", "Sunday")


def test_dates_read_alike_on_every_page_and_the_date_boxes_hint_says_so(
    client: TestClient, admin: User, session: Session, study_vehicle: Vehicle
) -> None:
    assert sign_in(client, ADMIN_EMAIL).status_code == 303
    today = long_date(local_today())  # 3 December 2026
    request = InspectionRequest(registration_number="BDG 252 QH", readings=STUDY)
    inspection = record_inspection(session, request=request, rules=get_settings().rules())
    home = client.get("/").text
    assert f'<p class="caption">{today}</p>' in home
    assert not [day for day in WEEKDAYS if day in home]
    assert f"Inspection No. {inspection.id} · {today}, " in client.get(f"/inspections/{inspection.id}").text
    for url in ("/inspections", "/admin/audit"):
        page = client.get(url).text
        assert f"For example, {today}</" in page, url  # not 2026-12-03, which no date box shows
    assert f"{today}</th>" in client.get("/statistics").text  # the day's row


def test_a_gap_reads_not_recorded_and_a_bracketed_station_name_gets_no_second_bracket(
    web: TestClient, session: Session, study_vehicle: Vehicle
) -> None:
    station, _key = create_station(session, name="Demo weighbridge (Agbara)")
    request = InspectionRequest(registration_number="BDG 252 QH", readings=STUDY)
    inspection = record_inspection(session, request=request, rules=get_settings().rules(), station=station)
    shown = web.get(f"/inspections/{inspection.id}").text
    assert 'id="recorded-by">Demo weighbridge (Agbara), weighbridge station<' in shown
    assert ") (" not in shown
    assert '<dd id="calibration">Not recorded</dd>' in shown
    vehicle = web.get("/vehicles/BDG252QH").text
    assert "<dt>Chassis number</dt><dd>Not recorded</dd>" in vehicle
    for other in ("Not given", "Not known", "not recorded"):
        assert other not in vehicle
    # The inputs too; an estimate that cannot be made without them stays "Not known".
    inputs = shown.split('id="estimates-inputs"', 1)[1].split("</dl>", 1)[0]
    assert "<dt>Rear track</dt><dd>Not recorded</dd>" in inputs
    assert "Not given" not in shown
