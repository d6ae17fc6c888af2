"""The officers' "Assess a model" pages: pick the model, see its vehicles, confirm, read the stored result."""

from __future__ import annotations

import re

from fastapi.testclient import TestClient
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from study_data import STUDY_TYPE_SPREAD

from app.type_assessments.models import TypeAssessmentRecord
from web.webtools import form_values, post_form, weigh_study_fleet

PICKED = "/type-assessments/new?make=Bajaj&model=RE&model_year=2012"


def cells(html: str, table_id: str) -> list[list[str]]:
    """The text of each body row's cells of one table."""
    table = html.split(f'id="{table_id}"', 1)[1].split("</table>", 1)[0]
    body = table.split("<tbody>", 1)[1]
    rows = re.findall(r"<tr>(.*?)</tr>", body, re.S)
    return [
        [re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<t[hd][^>]*>(.*?)</t[hd]>", r, re.S)]
        for r in rows
    ]


def test_an_officer_assesses_the_study_model_and_sees_section_7s_figures(
    web: TestClient, session: Session
) -> None:
    fleet = weigh_study_fleet(session)
    picking = web.get("/type-assessments/new")
    assert picking.status_code == 200
    assert "Bajaj RE (2012)</a>: 3 vehicles inspected" in picking.text
    page = web.get(PICKED)
    assert page.status_code == 200
    assert [row[0] for row in cells(page.text, "type-vehicles")] == sorted(
        fleet, key=lambda r: r.replace(" ", "")
    )
    assert "from these 3 vehicles" in page.text

    done = post_form(web, PICKED, "/type-assessments", {})
    assert done.status_code == 303, done.text
    shown = web.get(done.headers["location"])
    assert shown.status_code == 200
    assert "Type assessment recorded." in shown.text
    assert "Vehicles of this model must not carry passengers" in shown.text
    table4 = cells(shown.text, "table-4")
    assert [row[1:4] for row in table4] == [
        ["359.00", "250.00", "0.696"],
        ["431.00", "283.49", "0.658"],
        ["503.00", "342.18", "0.680"],
        ["575.00", "400.87", "0.697"],
        ["647.00", "459.56", "0.710"],
    ]
    spread = cells(shown.text, "type-spread")
    for row, (_n, low, mean, high, sd, upper, confident) in zip(spread, STUDY_TYPE_SPREAD, strict=True):
        assert row[1:6] == [f"{v:.5f}" for v in (low, mean, high, sd, upper)]
        assert row[6].startswith("C") if confident else row[6].startswith("NC")
    assert 'id="type-chart"' in shown.text
    assert shown.text.count('class="chart__vehicles"') == 5
    assert "chart__upper" in shown.text
    assert "chart__mean" in shown.text

    # The same form sent again goes to the first result; nothing is stored twice.
    form = form_values(web.get(PICKED).text)
    first = web.post("/type-assessments", data=form, follow_redirects=False)
    second = web.post("/type-assessments", data=form, follow_redirects=False)
    assert first.status_code == second.status_code == 303
    assert first.headers["location"] == second.headers["location"] != done.headers["location"]
    assert session.scalar(select(func.count()).select_from(TypeAssessmentRecord)) == 2


def test_a_model_with_one_vehicle_says_so_and_offers_no_assessment(
    web: TestClient, session: Session, study_vehicle: object
) -> None:
    page = web.get("/type-assessments/new?make=bajaj&model=re")
    assert page.status_code == 200
    assert 'id="shortage"' in page.text
    assert "at least two vehicles" in page.text
    assert 'action="/type-assessments"' not in page.text


def test_a_bad_model_year_is_refused_beside_the_field(web: TestClient) -> None:
    page = web.get("/type-assessments/new?make=Bajaj&model=RE&model_year=12x")
    assert page.status_code == 422
    assert re.search(r'id="model_year-error"[^>]*>.*1950 to 2100', page.text, re.S)
    missing = web.get("/type-assessments/new?make=Bajaj")
    assert missing.status_code == 422
    assert 'id="model-error"' in missing.text


def test_assess_a_model_is_in_the_navigation(web: TestClient) -> None:
    assert '<a href="/type-assessments/new"' in web.get("/").text
    assert web.get("/type-assessments/999").status_code == 404


def test_statistics_count_each_model_and_link_its_latest_type_assessment(
    web: TestClient, session: Session
) -> None:
    weigh_study_fleet(session)
    weigh_study_fleet(session, model="Maxima", suffix=" M")
    before = cells(web.get("/statistics").text, "per-model")
    assert [row[:4] for row in before] == [
        ["Bajaj Maxima", "3", "0", "0\u00a0%"],
        ["Bajaj RE", "3", "0", "0\u00a0%"],
    ]
    assert "None yet: assess the model" in before[1][4]
    done = post_form(web, PICKED, "/type-assessments", {})
    assert done.status_code == 303
    page = web.get("/statistics").text
    number = done.headers["location"].rsplit("/", 1)[-1]
    assert f'<a href="/type-assessments/{number}">No. {number}</a>' in page
    assert cells(page, "per-model")[1][4].startswith(f"No. {number}: NC")
