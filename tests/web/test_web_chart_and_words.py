"""The server-drawn SVG chart and the verdict in words."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from app.web.chart import ChartPoint, lsf_chart, y_range
from app.wording import occupancy_sentence, verdict_mark, verdict_sentence

SVG = "{http://www.w3.org/2000/svg}"
STUDY = [
    ChartPoint("Empty", "Empty (no occupants)", 0.6964, False),
    ChartPoint("Driver", "Driver", 0.6578, True),
    ChartPoint("+1", "Driver + 1 passenger", 0.6803, False),
    ChartPoint("+2", "Driver + 2 passengers", 0.6972, False),
    ChartPoint("+3", "Driver + 3 passengers", 0.7103, False),
]


def test_the_chart_is_well_formed_svg_with_a_text_alternative() -> None:
    svg = ET.fromstring(str(lsf_chart(STUDY)))
    assert svg.get("role") == "img"
    title = svg.find(f"{SVG}title")
    desc = svg.find(f"{SVG}desc")
    assert title is not None
    assert "Lateral Stability Factor" in (title.text or "")
    assert desc is not None
    assert "Driver: 0.658, C (compliant)" in (desc.text or "")
    assert "Empty (no occupants): 0.696, NC (not compliant)" in (desc.text or "")
    assert svg.get("aria-labelledby") == f"{title.get('id')} {desc.get('id')}"


def test_compliant_cases_are_circles_and_the_others_crosses_each_marked_in_words() -> None:
    svg = ET.fromstring(str(lsf_chart(STUDY)))
    points = svg.findall(f"{SVG}g")
    assert [p.get("data-verdict") for p in points] == ["NC", "C", "NC", "NC", "NC"]
    for point, case in zip(points, STUDY, strict=True):
        shape = point.find(f"{SVG}circle" if case.compliant else f"{SVG}path")
        assert shape is not None
        label = point.find(f"{SVG}text")
        assert label is not None
        assert label.text == ("C" if case.compliant else "NC")


def test_the_limit_line_sits_at_two_thirds_with_the_unstable_region_above_it() -> None:
    svg = ET.fromstring(str(lsf_chart(STUDY)))
    texts = [t.text for t in svg.iter(f"{SVG}text")]
    assert "limit 2/3" in texts
    assert "unstable" in texts
    for label in ("Empty", "Driver", "+1", "+2", "+3"):
        assert label in texts
    limit = next(line for line in svg.iter(f"{SVG}line") if line.get("class") == "chart__limit")
    shade = next(rect for rect in svg.iter(f"{SVG}rect") if rect.get("class") == "chart__unstable")
    top, bottom = 20.0, 340 - 60
    low, high = y_range([p.lsf for p in STUDY])
    expected = top + (high - 2 / 3) / (high - low) * (bottom - top)
    assert float(limit.get("y1", "0")) == pytest.approx(expected, abs=0.1)
    assert float(shade.get("y", "0")) == top
    assert float(shade.get("height", "0")) == pytest.approx(expected - top, abs=0.1)


def test_the_y_axis_runs_from_about_half_to_eight_tenths_and_widens_for_outliers() -> None:
    assert y_range([0.66, 0.7]) == pytest.approx((0.5, 0.8))
    assert y_range([0.45, 0.79]) == pytest.approx((0.4, 0.85))


def test_text_in_the_chart_is_escaped() -> None:
    svg = str(lsf_chart([ChartPoint("<b>", "<script>", 0.6, True)]))
    assert "<script>" not in svg
    assert "&lt;script&gt;" in svg


@pytest.mark.parametrize(
    ("cases", "best", "sentence"),
    [
        (
            [(0, False), (1, True), (2, False), (3, False), (4, False)],
            1,
            "Not compliant. Laterally stable with the driver alone; unstable with the driver and one or more "
            "passengers.",
        ),
        (
            [(0, True), (1, True), (2, True), (3, False)],
            2,
            "Not compliant. Laterally stable with the driver and up to one passenger; "
            "unstable with the driver and 2 passengers.",
        ),
        (
            [(0, True), (1, True), (2, True)],
            2,
            "Compliant. Laterally stable in every loading case, up to the driver and one passenger.",
        ),
        (
            [(0, True), (1, False), (2, False)],
            0,
            "Not compliant. Laterally unstable even with the driver alone.",
        ),
        (
            [(0, False), (1, True), (2, True)],
            2,
            "Not compliant. Laterally stable with the driver and up to one passenger; unstable when empty.",
        ),
    ],
)
def test_the_verdict_reads_as_one_plain_sentence(
    cases: list[tuple[int, bool]], best: int, sentence: str
) -> None:
    assert verdict_sentence(cases, best) == sentence


def test_the_occupancy_sentence_says_what_the_vehicle_may_carry() -> None:
    assert occupancy_sentence(True, 1) == "Certified for the driver alone: no passengers"
    assert occupancy_sentence(True, 2) == "Certified for the driver and up to one passenger"
    assert occupancy_sentence(True, 3) == "Certified for the driver and up to 2 passengers"
    assert (
        occupancy_sentence(False, 0)
        == "This vehicle must not be used: it is unstable even with the driver alone"
    )
    assert occupancy_sentence(False, 1) == "This vehicle must not carry passengers"
    assert occupancy_sentence(False, 3) == "This vehicle may carry the driver and up to 2 passengers, no more"


@pytest.mark.parametrize(("compliant", "mark"), [(True, "C"), (False, "NC")])
def test_a_verdict_is_marked_as_the_study_marks_it(compliant: bool, mark: str) -> None:
    assert verdict_mark(compliant) == mark
