"""The estimates, the stability map and the type assessment in a tadpole's and a quadricycle's words:
the map's limit line at 1/3 or 1/2 on the page and on the paper, the tyres and the front axle named as
the vehicle has them (reference section 9); the delta's words are checked by the older tests, unchanged.
"""

from __future__ import annotations

import html
import re
from typing import Any

import pytest
from fastapi.testclient import TestClient
from layout_vehicles import QUADRICYCLE, QUADRICYCLE_READINGS, TADPOLE, TADPOLE_READINGS
from sqlalchemy.orm import Session
from test_pdf_geometry import Word, pdftotext, words_of
from web.test_web_dynamics import text_of
from web.webtools import OFFICER_EMAIL, PASSWORD, sign_in

from app.accounts.service import create_user

VEHICLES = "/api/v1/vehicles"
INSPECTIONS = "/api/v1/inspections"
# Each layout, its readings, its limit as printed and as a number.
LAYOUTS = [
    pytest.param(TADPOLE, TADPOLE_READINGS, "1/3", 1 / 3, id="tadpole"),
    pytest.param(QUADRICYCLE, QUADRICYCLE_READINGS, "1/2", 1 / 2, id="quadricycle"),
]
MM = 72 / 25.4  # PDF points per millimetre


def weighed(api: TestClient, vehicle: dict[str, Any], readings: dict[str, Any]) -> int:
    """Register the vehicle and weigh it with a given CG height (so every rollover threshold is known)."""
    registered = api.post(VEHICLES, json=vehicle)
    assert registered.status_code == 201, registered.text
    answer = api.post(
        INSPECTIONS,
        json={
            "registration_number": vehicle["registration_number"],
            "readings": readings,
            "cg_height_m": 0.55,
        },
    )
    assert answer.status_code == 201, answer.text
    inspection_id: int = answer.json()["id"]
    return inspection_id


def officer(api: TestClient, session: Session) -> TestClient:
    """The same client, now an officer signed in rather than a station."""
    api.headers.pop("Authorization")
    create_user(session, email=OFFICER_EMAIL, password=PASSWORD, role="officer")
    assert sign_in(api, OFFICER_EMAIL).status_code == 303
    return api


def svg_of(html: str, element_id: str) -> str:
    match = re.search(rf'<svg[^>]*id="{element_id}".*?</svg>', html, re.S)
    assert match, f"no svg #{element_id}"
    return match.group(0)


def lsf_at(x: float, ticks: list[tuple[float, float]]) -> float:
    """The LSF at `x`, read off two tick marks of the axis (x, value)."""
    (x0, v0), (x1, v1) = ticks[0], ticks[-1]
    return v0 + (x - x0) * (v1 - v0) / (x1 - x0)


def svg_ticks(svg: str) -> list[tuple[float, float]]:
    """The map's LSF ticks: each label under the axis (two decimals) at its x."""
    labels = re.findall(
        r'<text x="([\d.]+)" y="(\d+\.\d)" text-anchor="middle" font-size="17">(0\.\d\d)</text>', svg
    )
    rows: dict[str, list[tuple[float, float]]] = {}
    for x, y, value in labels:
        rows.setdefault(y, []).append((float(x), float(value)))
    return max(rows.values(), key=len)


@pytest.mark.parametrize(("vehicle", "readings", "limit", "value"), LAYOUTS)
def test_the_map_on_the_page_draws_the_layout_s_limit(
    api: TestClient,
    session: Session,
    vehicle: dict[str, Any],
    readings: dict[str, Any],
    limit: str,
    value: float,
) -> None:
    inspection_id = weighed(api, vehicle, readings)
    page = officer(api, session).get(f"/inspections/{inspection_id}").text
    svg = svg_of(page, "stability-map")
    assert f"limit {limit}</text>" in svg
    assert "2/3" not in svg
    assert "0.667" not in svg
    description = text_of(svg, "stability-map-desc")
    assert f"Right of the {limit} line ({value:.3f}) a case is yaw-unstable." in description
    line = re.search(r'<line class="chart__limit" x1="([\d.]+)" x2="([\d.]+)"', svg)
    assert line
    assert line.group(1) == line.group(2)  # upright
    ticks = svg_ticks(svg)
    assert len(ticks) >= 4
    assert lsf_at(float(line.group(1)), ticks) == pytest.approx(value, abs=0.002)
    # Every case's marker stands at its own LSF on the same axis.
    lsfs = [float(v) for v in re.findall(r"LSF (0\.\d{3}), rollover threshold", description)]
    circles = re.findall(r'<path class="chart__nc" d="M([\d.]+) |<circle class="chart__c" cx="([\d.]+)"', svg)
    centres = [float(nc) + 7 if nc else float(c) for nc, c in circles if nc or c]
    legend = 2  # the legend's circle and cross come last
    assert [round(lsf_at(x, ticks), 2) for x in centres[:-legend]] == [round(v, 2) for v in lsfs]
    caption = text_of(page, "estimates").split("Stability map")[-1]
    assert f"Right of the dashed line at {limit} a case is yaw-unstable" in caption
    assert "2/3" not in caption


def test_a_tadpole_s_map_names_its_one_rear_wheel_and_says_rearward_load_worsens_both(
    api: TestClient, session: Session
) -> None:
    inspection_id = weighed(api, TADPOLE, TADPOLE_READINGS)
    page = officer(api, session).get(f"/inspections/{inspection_id}").text
    assert "LSF (share of weight on the rear wheel)" in svg_of(page, "stability-map")
    assert "with one rear wheel the rollover threshold falls as the LSF rises" in page
    assert "raises one and worsens the other" not in page
    inputs = html.unescape(text_of(page, "estimates-inputs"))
    assert "Rear track" not in inputs  # one rear wheel: no rear track
    assert "Front track 1.200 m" in inputs
    assert "Each front tyre's cornering stiffness" in inputs
    assert "Rear tyre cornering stiffness" in inputs
    assert "Each rear tyre" not in inputs
    assert "Centre of gravity behind the front wheels" in page


def test_a_quadricycle_s_map_says_what_rearward_load_does_with_two_rear_wheels(
    api: TestClient, session: Session
) -> None:
    inspection_id = weighed(api, QUADRICYCLE, QUADRICYCLE_READINGS)
    page = officer(api, session).get(f"/inspections/{inspection_id}").text
    assert "LSF (share of weight on the rear wheels)" in svg_of(page, "stability-map")
    assert "only as far as the rear track is wider than the front track" in page
    inputs = html.unescape(text_of(page, "estimates-inputs"))
    assert "Rear track 1.300 m" in inputs
    assert "Each front tyre's cornering stiffness" in inputs
    assert "Each rear tyre's cornering stiffness" in inputs


def map_ticks(words: list[Word]) -> list[Word]:
    """The paper's map's LSF ticks: the only row of two-decimal labels (the LSF chart's run upright)."""
    rows: dict[tuple[int, int], list[Word]] = {}
    for word in words:
        if re.fullmatch(r"0\.\d\d", word.text):
            rows.setdefault((word.page, round(word.y0)), []).append(word)
    row = max(rows.values(), key=len)
    assert len(row) >= 4
    return sorted(row, key=lambda w: w.x0)


@pytest.mark.parametrize(("vehicle", "readings", "limit", "value"), LAYOUTS)
def test_the_map_on_the_paper_draws_the_layout_s_limit(
    api: TestClient, vehicle: dict[str, Any], readings: dict[str, Any], limit: str, value: float
) -> None:
    inspection_id = weighed(api, vehicle, readings)
    issued = api.post(f"{INSPECTIONS}/{inspection_id}/certificate")
    assert issued.status_code == 201, issued.text
    pdf = api.get(f"/api/v1/certificates/{issued.json()['number']}/pdf").content
    text = " ".join(pdftotext(pdf=pdf).split())
    assert "Beyond the static test" in text
    assert "2/3" not in text
    words, _sizes = words_of(pdf)
    ticks = map_ticks(words)
    centres = [((w.x0 + w.x1) / 2, float(w.text)) for w in ticks]
    # The map's limit label starts 1 mm right of its line, level with the top of the plot.
    labels = [
        w
        for i, w in enumerate(words[:-1])
        if w.text == "limit"
        and words[i + 1].text == limit
        and w.page == ticks[0].page
        and ticks[0].x0 < w.x0 < ticks[-1].x1
        and 0 < ticks[0].y0 - w.y0 < 60 * MM
    ]
    assert len(labels) == 1, [w.text for w in words if w.page == ticks[0].page]
    assert lsf_at(labels[0].x0 - 1 * MM, centres) == pytest.approx(value, abs=0.005)
