"""The inspection page's "What would make it comply": the sentence, the GET form and its errors, the chart."""

from __future__ import annotations

import re
from decimal import Decimal

import pytest
from fastapi.testclient import TestClient
from sqlalchemy.orm import Session

from app.config import get_settings
from app.inspections.models import Inspection
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import WheelReadings
from app.vehicles.models import Vehicle

STUDY_SENTENCE = (
    "Carry no more than the driver; or fit more than 54.64 kg of ballast 0.30 m behind the front wheel; or "
    "move the rear bench 0.262 m forward, which still leaves the empty vehicle non-compliant; or fit rear "
    "tyres at least 1.226 times as stiff in cornering as the front."
)


def weigh(session: Session, front: str, left: str, right: str, overall: str | None = None) -> Inspection:
    readings = WheelReadings(
        (Decimal(front),), (Decimal(left),), (Decimal(right),), (Decimal(overall),) if overall else ()
    )
    return record_inspection(
        session,
        request=InspectionRequest(registration_number="BDG252QH", readings=readings),
        rules=get_settings().rules(),
    )


@pytest.fixture
def study(session: Session, study_vehicle: Vehicle) -> Inspection:
    return weigh(session, "108", "115", "135", "359")


def sentence(html: str) -> str:
    found = re.search(r'<p class="panel__remedies" id="remedies-sentence">(.*?)</p>', html, re.S)
    assert found is not None
    return found.group(1).replace("&#39;", "'")


def remedy_rows(html: str) -> list[list[str]]:
    body = html[html.index('id="remedies-table"') :]
    body = body[body.index("<tbody>") : body.index("</tbody>")]
    return [
        [re.sub(r"<[^>]+>", "", cell).strip() for cell in re.findall(r"<t[hd][^>]*>(.*?)</t[hd]>", row, re.S)]
        for row in re.findall(r"<tr>(.*?)</tr>", body, re.S)
    ]


def test_the_study_vehicle_page_says_what_would_make_it_comply(web: TestClient, study: Inspection) -> None:
    page = web.get(f"/inspections/{study.id}")
    assert page.status_code == 200
    assert "What would make it comply" in page.text
    assert sentence(page.text) == STUDY_SENTENCE
    assert remedy_rows(page.text) == [
        ["Empty (no occupants)", "0.696 NC", "0.624 C", "0.696 NC"],
        ["Driver", "0.658 C", "0.601 C", "0.658 C"],
        ["Driver + 1 passenger", "0.680 NC", "0.628 C", "0.662 C"],
        ["Driver + 2 passengers", "0.697 NC", "0.650 C", "0.664 C"],
        ["Driver + 3 passengers", "0.710 NC", "0.667 C", "0.667 C"],  # just below 2/3, decided exactly
    ]
    chart = page.text[page.text.index('id="remedy-chart"') :]
    assert "after fitting 54.64 kg of ballast 0.30 m behind the front wheel" in chart
    assert chart.count('data-series="before"') == 5
    assert chart.count('data-series="after"') == 5
    assert 'value="4"' in page.text
    assert 'value="0.30"' in page.text


def test_the_form_changes_the_target_the_position_and_the_chart(web: TestClient, study: Inspection) -> None:
    page = web.get(
        f"/inspections/{study.id}",
        params={"target_occupants": "2", "ballast_x_m": "-0,2", "remedy": "seat_shift"},
    )
    assert page.status_code == 200
    assert sentence(page.text) == (
        "Carry no more than the driver; or fit more than 13.92 kg of ballast 0.20 m ahead of the front "
        "wheel; or move the rear bench 0.191 m forward, which still leaves the empty vehicle non-compliant; "
        "or fit rear tyres at least 1.147 times as stiff in cornering as the front."
    )
    assert len(remedy_rows(page.text)) == 3
    assert "after moving the rear bench 0.191 m forward" in page.text
    assert 'id="remedy-seat_shift" name="remedy" value="seat_shift" checked' in page.text


def test_ballast_behind_two_thirds_says_it_cannot_help(web: TestClient, study: Inspection) -> None:
    page = web.get(f"/inspections/{study.id}", params={"ballast_x_m": "1.5"})
    assert page.status_code == 200
    assert sentence(page.text).endswith(
        "Ballast 1.50 m behind the front wheel cannot help: it must sit less than two thirds of the "
        "wheelbase behind the front wheel."
    )
    assert "Fitting front ballast cannot make every case comply, so there is nothing to chart." in page.text


@pytest.mark.parametrize(
    ("params", "input_id", "message"),
    [
        (
            {"target_occupants": "5"},
            "target_occupants",
            "Enter the number of occupants as a whole number from 0 to 4",
        ),
        ({"target_occupants": "two"}, "target_occupants", "Enter the number of occupants as a whole number"),
        (
            {"ballast_x_m": "front"},
            "ballast_x_m",
            "Enter the ballast position in metres behind the front wheel",
        ),
        (
            {"ballast_x_m": "3.5"},
            "ballast_x_m",
            "The distance behind the front wheel centre must be at least -1.0",
        ),
        (
            {"ballast_x_m": "0.12345"},
            "ballast_x_m",
            "Give the distance behind the front wheel centre to at most 4",
        ),
        (
            {"remedy": "prayer"},
            "remedy-ballast",
            "Choose fitting front ballast or moving the rear bench forward",
        ),
    ],
)
def test_a_bad_value_is_named_beside_its_field_and_kept(
    web: TestClient, study: Inspection, params: dict[str, str], input_id: str, message: str
) -> None:
    page = web.get(f"/inspections/{study.id}", params=params)
    assert page.status_code == 422
    assert f'<a href="#{input_id}">{message}' in page.text  # the summary links to the field
    beside = re.search(rf'<p id="{input_id}-error" class="error-message">(.*?)</p>', page.text, re.S)
    assert beside is not None
    assert message in beside.group(1)
    if input_id != "remedy-ballast":
        assert f'value="{next(iter(params.values()))}"' in page.text
        assert f'aria-describedby="{input_id}-hint {input_id}-error"' in page.text
    assert "What would make it comply" in page.text  # the defaults are shown meanwhile


def test_a_compliant_inspection_has_no_remedies_section(
    web: TestClient, session: Session, study_vehicle: Vehicle
) -> None:
    compliant = weigh(session, "220", "95", "95")
    page = web.get(f"/inspections/{compliant.id}", params={"target_occupants": "zzz"})
    assert page.status_code == 200
    assert "What would make it comply" not in page.text
