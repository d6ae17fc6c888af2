"""Beyond the static test on the pages: the vehicle's figures form (every change kept, audited), the
lift weighing on the inspection form, the estimates beside their inputs and the stability map."""

from __future__ import annotations

import math
import re
from decimal import Decimal

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from sqlalchemy.orm import Session

from app.audit.models import AuditEvent
from app.config import get_settings
from app.dynamics.models import VehicleDynamicsRevision
from app.vehicles.models import Vehicle
from app.web.chart import MapPoint, map_geometry
from web.webtools import STUDY_READINGS, post_form

FIGURES_URL = "/vehicles/BDG252QH/dynamics"
FORM_URL = "/vehicles/BDG252QH/inspections/new"
ILLUSTRATIVE = {
    "track_m": "1.15",
    "wheel_radius_m": "0.19",
    "seat_z_m_0": "0.75",
    "seat_z_m_1": "0.80",
    "seat_z_m_2": "0.80",
    "seat_z_m_3": "0.80",
    "front_cornering_stiffness_n_per_rad": "8000",
    "rear_cornering_stiffness_n_per_rad": "8000",
    "drag_area_m2": "1.6",
    "centre_of_pressure_height_m": "0.9",
}
LIFT = {"cg_lift_height_m": "0.40", "cg_front_kg_1": "94.8"}


def text_of(html: str, element_id: str) -> str:
    """The visible text of the element with this id (up to its closing tag of the same name)."""
    match = re.search(rf'<(\w+)[^>]*id="{element_id}"', html)
    assert match, f"no #{element_id}"
    tag = match.group(1)
    body = html[match.start() : html.index(f"</{tag}>", match.start())]
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", body)).strip()


def record_figures(web: TestClient, fields: dict[str, str]) -> None:
    done = post_form(web, FIGURES_URL, FIGURES_URL, fields)
    assert done.status_code == 303, done.text


def test_every_change_of_the_figures_is_a_new_revision_kept_and_audited(
    web: TestClient, study_vehicle: Vehicle, session: Session
) -> None:
    record_figures(web, ILLUSTRATIVE)
    record_figures(web, {"track_m": "1.200"})
    record_figures(web, {"track_m": "1.2"})  # the same figure: nothing new is recorded
    session.expire_all()
    revisions = session.scalars(
        select(VehicleDynamicsRevision).order_by(VehicleDynamicsRevision.revision)
    ).all()
    assert [(r.revision, r.track_m) for r in revisions] == [
        (1, None),
        (2, Decimal("1.1500")),
        (3, Decimal("1.2000")),
    ]
    assert revisions[1].seat_heights_m == ["0.75", "0.80", "0.80", "0.80"]
    page = web.get("/vehicles/BDG252QH").text
    assert "Revision 3; earlier revisions are kept." in page
    assert "1.2" in text_of(page, "vehicle-figures")
    recorded = select(AuditEvent).where(AuditEvent.action == "vehicle.dynamics_recorded")
    events = session.scalars(recorded.order_by(AuditEvent.id)).all()
    assert len(events) == 3  # revision 1 at registration, then the two changes
    assert [e.actor_label for e in events[1:]] == ["officer@example.org"] * 2


@pytest.mark.parametrize(
    ("fields", "field", "words"),
    [
        ({"track_m": "wide"}, "track_m", "as a number"),
        ({"track_m": "0"}, "track_m", "must be more than 0"),
        ({"seat_z_m_1": "0.1"}, "seat_z_m_1", "between 0.2 and 2.0"),
        (
            {"front_cornering_stiffness_n_per_rad": "-8000"},
            "front_cornering_stiffness_n_per_rad",
            "more than 0",
        ),
        ({"drag_area_m2": "1.60001"}, "drag_area_m2", "decimal places"),
    ],
)
def test_an_impossible_figure_comes_back_beside_its_field_and_nothing_is_recorded(
    web: TestClient, study_vehicle: Vehicle, session: Session, fields: dict[str, str], field: str, words: str
) -> None:
    answer = post_form(web, FIGURES_URL, FIGURES_URL, {**ILLUSTRATIVE, **fields})
    assert answer.status_code == 422
    assert words in text_of(answer.text, f"{field}-error")
    assert 'class="error-summary' in answer.text or "There is a problem" in answer.text
    session.expire_all()
    assert len(session.scalars(select(VehicleDynamicsRevision)).all()) == 1


def test_the_inspection_page_shows_the_estimates_beside_their_inputs_and_the_map(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    record_figures(web, ILLUSTRATIVE)
    done = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, **LIFT})
    assert done.status_code == 303, done.text
    page = web.get(done.headers["location"]).text
    section = text_of(page, "estimates")
    assert "Beyond the static test (estimates, not part of the verdict)" in section
    table = text_of(page, "estimates-table")
    for figure in (
        "0.5503 m",
        "0.7277 g",
        "36.04°",
        "113.8 km/h",
        "0.6480 g",
        "427.9 N·m/rad",
        "None (understeers)",
        "70.0 km/h",
    ):
        assert figure in table
    inputs = text_of(page, "estimates-inputs")
    for shown in (
        "1.150 m",
        "0.190 m",
        "0.75, 0.80, 0.80, 0.80 m",
        "0.400 m",
        "94.8 kg",
        "8000 N/rad",
        "revision 2",
    ):
        assert shown in inputs
    svg = page[page.index('id="stability-map"') :]
    assert len(re.findall(r'class="chart__point"', svg[: svg.index("</svg>")])) == 5
    assert "chart__min-rollover" not in svg[: svg.index("</svg>")]
    # the verdict stays the static one
    assert "C Compliant" in text_of(page, "table-4")


def test_a_minimum_rollover_threshold_draws_its_line(
    web: TestClient, study_vehicle: Vehicle, monkeypatch: pytest.MonkeyPatch
) -> None:
    record_figures(web, ILLUSTRATIVE)
    done = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, **LIFT})
    monkeypatch.setenv("TRIKECERT_MIN_ROLLOVER_G", "0.65")
    get_settings.cache_clear()
    try:
        page = web.get(done.headers["location"]).text
    finally:
        monkeypatch.delenv("TRIKECERT_MIN_ROLLOVER_G")
        get_settings.cache_clear()
    svg = page[page.index('id="stability-map"') :]
    svg = svg[: svg.index("</svg>")]
    assert "chart__min-rollover" in svg
    assert "minimum 0.65 g" in svg
    assert "The minimum rollover threshold is 0.65 g" in svg


def test_without_figures_the_page_says_what_is_missing_and_draws_no_map(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    done = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS)
    page = web.get(done.headers["location"]).text
    missing = text_of(page, "estimates-missing")
    assert "the rear track" in missing
    assert "the centre of gravity height" in missing
    assert 'id="stability-map"' not in page
    assert 'id="estimates-table"' not in page


def test_a_raised_reading_heavier_than_level_comes_back_beside_its_box(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    record_figures(web, ILLUSTRATIVE)
    answer = post_form(
        web, FORM_URL, FORM_URL, {**STUDY_READINGS, "cg_lift_height_m": "0.4", "cg_front_kg_1": "110"}
    )
    assert answer.status_code == 422
    assert "must carry less than level" in text_of(answer.text, "cg_front_kg_1-error")
    answer = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, "cg_front_kg_1": "94.8"})
    assert answer.status_code == 422
    assert "how far the front wheel was raised" in text_of(answer.text, "cg_lift_height_m-error")


def test_the_map_widens_its_axes_to_hold_every_point_and_the_minimum_line() -> None:
    points = [MapPoint("None", "None", 0.52, 0.45, True), MapPoint("Driver", "Driver", 0.83, 0.7, False)]
    geometry = map_geometry(points, 1.05)
    assert geometry.x_ticks[0][1] == "0.45"
    assert geometry.x_ticks[-1][1] == "0.90"
    assert geometry.y_ticks[0][1] == "0.4"
    assert geometry.y_ticks[-1][1] == "1.1"
    assert geometry.min_rollover is not None
    assert all(0 < across < 1 and 0 < up < 1 for across, up, _ in geometry.points)
    assert 0 < geometry.min_rollover[0] < 1
    assert 0 < geometry.limit_x < 1


def test_each_remedy_shows_what_it_does_to_the_rollover_threshold(
    web: TestClient, study_vehicle: Vehicle
) -> None:
    record_figures(web, ILLUSTRATIVE)
    done = post_form(web, FORM_URL, FORM_URL, {**STUDY_READINGS, **LIFT})
    page = web.get(done.headers["location"]).text
    table = text_of(page, "remedies-rollover-table")
    # Worked out here: the lift's CG height, the full case's height, its rear load and the advised
    # remedies (54.64 kg at 0.30 m; the rear bench 0.262 m forward), each at its own LSF.
    tan_phi = math.tan(math.asin(0.40 / 2.0))
    h0 = 0.19 + 2.0 * (108 - 94.8) / (359 * tan_phi)
    h3 = (359 * h0 + 72 * (0.75 + 3 * 0.80)) / 647
    rear3 = 250 + 72 * 0.9303 / 2 + 3 * 72 * 1.6303 / 2
    today = 1.15 / (2 * h3) * rear3 / 647
    with_ballast = 1.15 / (2 * h3) * (rear3 + 54.64 * 0.30 / 2) / (647 + 54.64)
    with_bench = 1.15 / (2 * h3) * (rear3 - 3 * 72 * 0.262 / 2) / 647
    row = table[table.index("Driver + 3 passengers") :]
    assert row.split()[4:7] == [f"{today:.4f}", "g", f"{with_ballast:.4f}"]
    assert f"{with_bench:.4f} g" in row
    assert f"{today:.4f}" == "0.6227"  # the reference's figure for the full taxi
    assert with_bench < today  # moving load forward costs rollover margin
    empty = "Empty (no occupants)"
    none_row = [empty, *table[table.index(empty) + len(empty) : table.index("Driver")].split()]
    assert none_row[1] == none_row[5] == "0.7277"  # no passenger: moving the bench changes nothing


def test_without_figures_the_remedies_show_no_rollover_table(web: TestClient, study_vehicle: Vehicle) -> None:
    done = post_form(web, FORM_URL, FORM_URL, STUDY_READINGS)
    page = web.get(done.headers["location"]).text
    assert "What would make it comply" in page
    assert 'id="remedies-rollover-table"' not in page
