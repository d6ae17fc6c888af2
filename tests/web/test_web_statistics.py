"""The statistics page: totals, per station and per day for a period; certificates issued and
revoked; bad filters re-rendered with their messages; the same counts as CSV; sign-in required."""

from __future__ import annotations

import csv
import io
import re
from collections.abc import Callable
from datetime import timedelta

from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.certificates.actors import Actor
from app.certificates.service import issue_certificate, revoke_certificate
from app.config import get_settings
from app.db import utcnow
from app.inspections.models import Inspection
from app.vehicles.models import Vehicle
from app.web.formatting import local_today, long_date
from web.webtools import STUDY_READINGS, post_form

FORM_URL = "/vehicles/BDG252QH/inspections/new"


def record(web: TestClient, front: str = "108") -> int:
    response = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, "front_kg_1": front, "overall_kg_1": ""})
    assert response.status_code == 303, response.text
    return int(response.headers["location"].rsplit("/", 1)[1])


def totals(html: str) -> list[tuple[str, str]]:
    block = html[html.index('id="totals"') :]
    return re.findall(r'<span class="count">([^<]+)</span> ([a-z ]+)</li>', block[: block.index("</ul>")])


def test_the_page_counts_the_period_per_station_and_per_day(
    web: TestClient, study_vehicle: Vehicle, session: Session, backdate: Callable[..., None]
) -> None:
    compliant = record(web, front="250")
    # Certified before the vehicle is weighed again: the records refuse a contradicted weighing's paper.
    issued = issue_certificate(
        session, inspection_id=compliant, actor=Actor.of_cli(), settings=get_settings()
    )
    revoke_certificate(
        session, number=issued.certificate.number, actor=Actor("admin", admin=True), reason="Weighed wrongly"
    )
    record(web)
    old = record(web)
    backdate(old, utcnow() - timedelta(days=40))

    page = web.get("/statistics")

    assert page.status_code == 200
    assert totals(page.text) == [
        ("2", "inspections"),
        ("1", "compliant"),
        ("1", "not compliant"),
        ("50 %", "compliant share"),
    ], "the inspection 40 days ago is outside the default 30 days"
    assert "Certificates issued in the period: 1 compliant, 0 refusals; 1 revoked." in page.text
    per_station = page.text[page.text.index('id="per-station"') :]
    assert re.search(
        r"Officers \(browser\)</th>\s*<td[^>]*>2</td>\s*<td[^>]*>1</td>\s*<td[^>]*>1</td>", per_station
    )
    today = local_today()
    per_day = page.text[page.text.index('id="per-day"') :]
    assert per_day.count("<tr>") == 1 + 30, "a heading row and every day of the period, empty days too"
    assert re.search(rf"{long_date(today)}</th>\s*<td[^>]*>2</td>", per_day), "newest day first"

    wider = web.get(f"/statistics?from={(today - timedelta(days=45)).isoformat()}")
    assert totals(wider.text)[0] == ("3", "inspections")


def test_a_bad_period_is_rerendered_with_the_message_beside_the_field(web: TestClient) -> None:
    today = local_today()
    backwards = web.get(f"/statistics?from={today.isoformat()}&to={(today - timedelta(days=3)).isoformat()}")
    too_long = web.get(f"/statistics?from={(today - timedelta(days=400)).isoformat()}")
    not_a_date = web.get("/statistics?to=last+week&station=x")
    out_of_range = [
        web.get(f"/statistics?{q}") for q in ("to=0001-01-01", "to=9999-12-31", "from=0001-01-01")
    ]

    assert backwards.status_code == too_long.status_code == not_a_date.status_code == 422
    assert '<a href="#to">The &#39;to&#39; date must be the same as or after the &#39;from&#39; date</a>' in (
        backwards.text
    )
    assert "Choose a period of at most 366 days" in too_long.text
    assert '<a href="#to">Enter the date as year-month-day, like 2026-11-23</a>' in not_a_date.text
    assert '<a href="#station">Choose a station from the list</a>' in not_a_date.text
    assert 'value="last week"' in not_a_date.text, "the entered value stays"
    for page in out_of_range:
        assert page.status_code == 422, page.text
        assert "Enter a date from 1 January 2000 to 31 December 2099" in page.text


def test_the_csv_has_one_row_per_day_with_the_counts(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    record(web, front="250")
    record(web)
    today = local_today()

    response = web.get(f"/statistics.csv?from={(today - timedelta(days=2)).isoformat()}")

    assert response.status_code == 200
    assert response.headers["content-type"].startswith("text/csv")
    assert "attachment" in response.headers["content-disposition"]
    rows = list(csv.reader(io.StringIO(response.text)))
    assert rows[0] == ["date", "inspections", "compliant", "not_compliant"]
    assert [r[0] for r in rows[1:]] == [(today - timedelta(days=n)).isoformat() for n in (2, 1, 0)]
    assert rows[-1] == [today.isoformat(), "2", "1", "1"]
    assert session.scalar(select(Inspection.id).limit(1)) is not None


def test_the_statistics_need_a_signed_in_user(client: TestClient) -> None:
    for url in ("/statistics", "/statistics.csv"):
        response = client.get(url, follow_redirects=False)
        assert response.status_code == 303
        assert response.headers["location"].startswith("/login")
