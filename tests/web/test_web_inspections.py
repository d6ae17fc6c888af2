"""The new-inspection form, the result page (Table 4, verdict, chart) and the lists."""

from __future__ import annotations

import re
from collections.abc import Callable
from datetime import timedelta

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app import config
from app.db import utcnow
from app.inspections.models import Inspection
from app.stations.service import create_station
from app.vehicles.models import Vehicle
from app.web.formatting import local_today
from web.webtools import STUDY_READINGS, form_values, post_form

FORM_URL = "/vehicles/BDG252QH/inspections/new"


def count(session: Session) -> int:
    session.expire_all()
    return session.scalar(select(func.count()).select_from(Inspection)) or 0


def table_rows(html: str) -> list[list[str]]:
    """The cells of Table 4 as text."""
    body = html[html.index('id="table-4"') :]
    body = body[body.index("<tbody>") : body.index("</tbody>")]
    rows = []
    for row in re.findall(r"<tr>(.*?)</tr>", body, re.S):
        cells = re.findall(r"<t[hd][^>]*>(.*?)</t[hd]>", row, re.S)
        rows.append([re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", c)).strip() for c in cells])
    return rows


def test_the_form_is_prefilled_from_the_vehicle_and_the_settings(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    values = form_values(web.get(FORM_URL).text)
    assert values["wheelbase_m"] == "2.000"
    assert values["occupant_mass_kg"] == "72"
    assert [values[f"seat_x_m_{i}"] for i in range(4)] == ["0.9303", "1.6303", "1.6303", "1.6303"]
    assert values["front_kg_1"] == ""


def test_the_study_vehicle_gets_table_4_with_c_only_for_the_driver_alone(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    response = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS)
    assert response.status_code == 303
    page = web.get(response.headers["location"])
    assert page.status_code == 200
    assert table_rows(page.text) == [
        ["Empty (no occupants)", "359.00", "250.00", "0.696", "2/3 (0.667)", "-0.030", "NC Not compliant"],
        ["Driver", "431.00", "283.49", "0.658", "2/3 (0.667)", "+0.009", "C Compliant"],
        ["Driver + 1 passenger", "503.00", "342.18", "0.680", "2/3 (0.667)", "-0.014", "NC Not compliant"],
        ["Driver + 2 passengers", "575.00", "400.87", "0.697", "2/3 (0.667)", "-0.031", "NC Not compliant"],
        ["Driver + 3 passengers", "647.00", "459.56", "0.710", "2/3 (0.667)", "-0.044", "NC Not compliant"],
    ]
    assert (
        "Not compliant. Laterally stable with the driver alone; unstable with the driver and one or more "
        "passengers." in page.text
    )
    assert '<strong id="occupancy">This vehicle must not carry passengers</strong>' in page.text
    assert "<svg" in page.text
    assert "limit 2/3" in page.text
    assert count(session) == 1
    stored = session.scalars(select(Inspection)).one()
    assert stored.user_id is not None


def test_repeated_readings_are_averaged_and_blank_boxes_ignored(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    readings = {**STUDY_READINGS, "front_kg_1": "107.5", "front_kg_2": "", "front_kg_3": "108.5"}
    response = post_form(web, FORM_URL, FORM_URL, readings)
    assert response.status_code == 303
    stored = session.scalars(select(Inspection)).one()
    assert stored.front_kg == 108
    assert sorted(str(r.value_kg) for r in stored.readings if r.wheel == "front_kg") == ["107.500", "108.500"]
    assert "(mean of 107.5, 108.5)" in web.get(response.headers["location"]).text


def test_a_reading_that_is_not_a_number_is_shown_beside_its_box_and_nothing_is_stored(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, "left_rear_kg_2": "11S"})
    assert response.status_code == 422
    html = response.text
    message = "Enter the left rear wheel reaction as a number of kilograms, like 108.5"
    assert f'<a href="#left_rear_kg_2">{message}</a>' in html
    error = '<span class="visually-hidden">Error:</span> '
    assert f'id="left_rear_kg_2-error" class="error-message">{error}{message}' in html
    assert form_values(html)["left_rear_kg_2"] == "11S"
    assert form_values(html)["front_kg_1"] == "108"
    assert count(session) == 0


def test_the_cores_refusal_of_a_wheel_sum_names_both_figures_beside_the_overall_weight(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, "overall_kg_1": "400"})
    assert response.status_code == 422
    assert (
        '<a href="#overall_kg_1">The three wheel readings add up to 358 kg but the overall weight is 400 kg; '
        "the difference (10.5\u00a0%) is more than the allowed 1\u00a0%. Weigh the vehicle again.</a>"
        in response.text
    )
    assert 'id="overall_kg_1-error"' in response.text
    assert count(session) == 0


def test_a_missing_wheel_is_asked_for(web: TestClient, study_vehicle: Vehicle, session: Session) -> None:
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, "right_rear_kg_1": ""})
    assert response.status_code == 422
    assert (
        '<a href="#right_rear_kg_1">Give at least one reading of the right rear wheel reaction</a>'
        in response.text
    )
    assert count(session) == 0


def test_a_double_clicked_submit_is_stored_once_and_both_answers_lead_to_the_same_result(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    data = {**form_values(web.get(FORM_URL).text), **STUDY_READINGS}
    first = web.post(FORM_URL, data=data, follow_redirects=False)
    second = web.post(FORM_URL, data=data, follow_redirects=False)
    assert first.status_code == second.status_code == 303
    assert first.headers["location"] == second.headers["location"]
    assert count(session) == 1


def test_a_measured_case_replaces_the_calculated_row(web: TestClient, study_vehicle: Vehicle) -> None:
    measured = {
        "measured_2_front_kg": "170",
        "measured_2_left_rear_kg": "165",
        "measured_2_right_rear_kg": "168",
    }
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, **measured})
    assert response.status_code == 303
    rows = table_rows(web.get(response.headers["location"]).text)
    assert rows[2][:4] == ["Driver + 1 passenger (weighed)", "503.00", "333.00", "0.662"]
    assert rows[2][-1] == "C Compliant"


def test_a_measured_case_without_its_front_wheel_is_refused_beside_that_box(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    measured = {"measured_2_left_rear_kg": "165", "measured_2_right_rear_kg": "168"}
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, **measured})
    assert response.status_code == 422
    assert 'href="#measured_2_front_kg"' in response.text
    assert "<details open>" in response.text
    assert count(session) == 0


def test_an_unknown_inspection_is_a_404_page(web: TestClient) -> None:
    response = web.get("/inspections/999", headers={"accept": "text/html"})
    assert response.status_code == 404
    assert "inspection 999 does not exist" in response.text.lower()


def record(web: TestClient, overall: str = "359") -> str:
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, "overall_kg_1": overall})
    assert response.status_code == 303
    return str(response.headers["location"])


def test_the_home_page_counts_todays_inspections(
    web: TestClient, study_vehicle: Vehicle, session: Session, backdate: Callable[..., None]
) -> None:
    record(web)
    record(web)
    old = session.scalars(select(Inspection)).first()
    assert old is not None
    backdate(old.id, utcnow() - timedelta(days=3))
    html = web.get("/").text
    counts = re.findall(r'<span class="count">(\d+)</span> ([a-z ]+)</li>', html)
    assert counts == [("1", "inspections"), ("0", "compliant"), ("1", "not compliant")]


def test_the_list_filters_by_verdict_station_and_dates_and_pages(
    web: TestClient,
    study_vehicle: Vehicle,
    session: Session,
    monkeypatch: pytest.MonkeyPatch,
    backdate: Callable[..., None],
) -> None:
    station, _key = create_station(session, name="Agbara weighbridge")
    for _ in range(3):
        record(web)
    first = session.scalars(select(Inspection).order_by(Inspection.id)).first()
    assert first is not None
    backdate(first.id, utcnow() - timedelta(days=10), station_id=station.id)

    monkeypatch.setenv("TRIKECERT_PAGE_SIZE", "2")
    config.get_settings.cache_clear()
    try:
        page_one = web.get("/inspections")
        assert "Showing 1 to 2 of 3 inspections" in page_one.text
        assert 'href="/inspections?page=2" rel="next"' in page_one.text
        assert "Showing 3 to 3 of 3" in web.get("/inspections?page=2").text
        assert "of 1 inspection," in web.get(f"/inspections?station={station.id}").text
        assert "No inspections match" in web.get("/inspections?verdict=compliant").text
        assert "of 3 inspections" in web.get("/inspections?verdict=not-compliant").text
        today = local_today().isoformat()
        assert "of 2 inspections" in web.get(f"/inspections?from={today}").text
        bad = web.get("/inspections?from=yesterday")
        assert bad.status_code == 422
        assert '<a href="#from">Enter the date as year-month-day, like 2026-11-23</a>' in bad.text
    finally:
        monkeypatch.delenv("TRIKECERT_PAGE_SIZE")
        config.get_settings.cache_clear()


def test_a_date_no_day_bound_can_hold_is_refused_beside_its_field(web: TestClient) -> None:
    for query in ("to=9999-12-31", "from=0001-01-01", "from=9999-12-31"):
        page = web.get(f"/inspections?{query}")
        field = query.split("=")[0]
        assert page.status_code == 422, (query, page.text)
        assert f'<a href="#{field}">Enter a date from 1 January 2000 to 31 December 2099</a>' in page.text


def test_the_vehicles_page_shows_its_latest_table_4_and_chart(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    record(web)
    html = web.get("/vehicles/BDG252QH").text
    assert [row[-1] for row in table_rows(html)] == [
        "NC Not compliant",
        "C Compliant",
        "NC Not compliant",
        "NC Not compliant",
        "NC Not compliant",
    ]
    assert 'id="lsf-chart"' in html
    assert '<strong id="occupancy">This vehicle must not carry passengers</strong>' in html
