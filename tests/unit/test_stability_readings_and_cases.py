"""Repeated readings, directly measured loading cases and load items.

Most tests start from the paper's vehicle (a = 108, b = 115, c = 135, W = 359, WB = 2.000 m, driver at
0.9303 m, three passengers at 1.6303 m, 72 kg), whose computed cases are, exactly:
    total 359, 431, 503, 575, 647   rear 250, 283.4908, 342.1816, 400.8724, 459.5632
"""

from __future__ import annotations

from dataclasses import replace
from decimal import Decimal
from fractions import Fraction

import pytest

from app.stability import (
    Assessment,
    AssessmentInput,
    LoadItem,
    MeasuredCase,
    Seat,
    StabilityError,
    WheelReadings,
    assess,
)


def kg(*values: str) -> tuple[Decimal, ...]:
    return tuple(Decimal(v) for v in values)


def wheels(front: str, left: str, right: str, overall: str | None = None) -> WheelReadings:
    return WheelReadings(kg(front), kg(left), kg(right), kg(overall) if overall is not None else ())


PAPER_VEHICLE = AssessmentInput(
    readings=wheels("108", "115", "135", "359"),
    wheelbase_m=Decimal("2.000"),
    seats=(Seat("driver", Decimal("0.9303")), *(Seat("passenger", Decimal("1.6303")),) * 3),
    occupant_mass_kg=Decimal("72"),
)
COMPUTED_TOTALS = [Fraction(359), Fraction(431), Fraction(503), Fraction(575), Fraction(647)]
COMPUTED_REARS = [Fraction(v) for v in ("250", "283.4908", "342.1816", "400.8724", "459.5632")]


def verdicts(assessment: Assessment) -> str:
    return " ".join("C" if case.compliant else "NC" for case in assessment.cases)


# ---------------------------------------------------------------------------------------------------------
# Repeated readings


@pytest.mark.parametrize(
    ("readings", "means", "overall", "spreads"),
    [
        pytest.param(
            WheelReadings(kg("108", "108", "109"), kg("115"), kg("135")),
            (Fraction(325, 3), Fraction(115), Fraction(135)),
            None,
            {"front_kg": Fraction(1), "left_rear_kg": Fraction(0), "right_rear_kg": Fraction(0)},
            id="108-108-109-averages-to-325/3",
        ),
        pytest.param(
            WheelReadings(
                kg("107.5", "108.5"),
                kg("114.9", "115.1", "115.0"),
                kg("135", "135.2"),
                kg("359", "359.5", "358.5"),
            ),
            (Fraction(108), Fraction(115), Fraction("135.1")),
            Fraction(359),
            {
                "front_kg": Fraction(1),
                "left_rear_kg": Fraction("0.2"),
                "right_rear_kg": Fraction("0.2"),
                "overall_kg": Fraction(1),
            },
            id="every-wheel-and-the-overall-weight-repeated",
        ),
        pytest.param(
            WheelReadings(kg("100.001", "100.002"), kg("100"), kg("100")),
            (Fraction(200_003, 2000), Fraction(100), Fraction(100)),
            None,
            {"front_kg": Fraction(1, 1000), "left_rear_kg": Fraction(0), "right_rear_kg": Fraction(0)},
            id="gram-resolution-mean-kept-exact",
        ),
    ],
)
def test_repeated_readings_are_averaged_exactly_and_their_spread_is_reported(
    readings: WheelReadings,
    means: tuple[Fraction, Fraction, Fraction],
    overall: Fraction | None,
    spreads: dict[str, Fraction],
) -> None:
    assessment = assess(replace(PAPER_VEHICLE, readings=readings))
    averaged = assessment.readings
    assert (averaged.front_kg, averaged.left_rear_kg, averaged.right_rear_kg) == means
    assert averaged.overall_kg == overall
    assert averaged.spread_kg == spreads
    empty = assessment.cases[0]
    assert empty.total_kg == (overall if overall is not None else sum(means))
    assert empty.rear_kg == means[1] + means[2]


def test_a_mean_of_thirds_is_not_rounded_on_its_way_into_the_cases() -> None:
    assessment = assess(
        replace(PAPER_VEHICLE, readings=WheelReadings(kg("108", "108", "109"), kg("115"), kg("135")))
    )
    assert assessment.cases[0].total_kg == Fraction(1075, 3)
    assert assessment.cases[1].total_kg == Fraction(1075, 3) + 72
    assert assessment.cases[0].lsf == Fraction(750, 1075)


# ---------------------------------------------------------------------------------------------------------
# Measured cases


@pytest.mark.parametrize(
    ("measured", "expected", "verdict_line", "max_occupants"),
    [
        pytest.param(
            (MeasuredCase(2, wheels("173", "160", "170", "504")),),
            {2: (Fraction(504), Fraction(330))},  # 330/504 = 55/84 < 2/3: turns case 3 from NC to C
            "NC C C NC NC",
            2,
            id="driver+1-weighed-with-overall-weight",
        ),
        pytest.param(
            (MeasuredCase(4, wheels("190", "225", "230")),),
            {4: (Fraction(645), Fraction(455))},  # no overall weight: total = 190 + 225 + 230
            "NC C NC NC NC",
            1,
            id="full-load-weighed-without-overall-weight",
        ),
        pytest.param(
            (MeasuredCase(1, WheelReadings(kg("147", "148"), kg("135"), kg("149"))),),
            {1: (Fraction("431.5"), Fraction(284))},  # front read twice: 147.5
            "NC C NC NC NC",
            1,
            id="driver-weighed-with-repeated-readings",
        ),
        pytest.param(
            (
                MeasuredCase(3, wheels("180", "190", "200", "570")),
                MeasuredCase(1, wheels("175", "120", "136")),
            ),
            {1: (Fraction(431), Fraction(256)), 3: (Fraction(570), Fraction(390))},
            "NC C NC NC NC",
            1,
            id="two-cases-weighed-in-any-order",
        ),
    ],
)
def test_a_measured_case_replaces_the_computed_one_and_only_that_one(
    measured: tuple[MeasuredCase, ...],
    expected: dict[int, tuple[Fraction, Fraction]],
    verdict_line: str,
    max_occupants: int,
) -> None:
    assessment = assess(replace(PAPER_VEHICLE, measured_cases=measured))
    for case in assessment.cases:
        if case.occupants in expected:
            total, rear = expected[case.occupants]
            assert case.measured is True
        else:
            total, rear = COMPUTED_TOTALS[case.occupants], COMPUTED_REARS[case.occupants]
            assert case.measured is False
        assert (case.total_kg, case.rear_kg) == (total, rear)
    assert verdicts(assessment) == verdict_line
    assert assessment.max_compliant_occupants == max_occupants


def test_a_measured_case_is_taken_as_weighed_without_adding_the_load_items() -> None:
    data = replace(
        PAPER_VEHICLE,
        load_items=(LoadItem(Decimal("20"), Decimal("2.5")),),
        measured_cases=(MeasuredCase(2, wheels("173", "160", "170", "504")),),
    )
    cases = assess(data).cases
    assert (cases[2].total_kg, cases[2].rear_kg, cases[2].measured) == (Fraction(504), Fraction(330), True)
    # the computed cases either side still carry the 20 kg item at 2.5 m (+25 kg on the rear)
    assert (cases[1].total_kg, cases[1].rear_kg) == (Fraction(451), Fraction("308.4908"))
    assert (cases[3].total_kg, cases[3].rear_kg) == (Fraction(595), Fraction("425.8724"))


@pytest.mark.parametrize(
    ("occupant_counts", "field", "rule", "words"),
    [
        pytest.param((0,), "measured_cases[0].occupants", "range", "between 1 and 4", id="zero-occupants"),
        pytest.param((-1,), "measured_cases[0].occupants", "range", "got -1", id="negative-occupants"),
        pytest.param((5,), "measured_cases[0].occupants", "range", "got 5", id="more-occupants-than-seats"),
        pytest.param(
            (1, 9), "measured_cases[1].occupants", "range", "between 1 and 4", id="second-one-out-of-range"
        ),
        pytest.param(
            (2, 2), "measured_cases[1].occupants", "duplicate", "measured twice", id="same-count-twice"
        ),
        pytest.param(
            (3, 1, 3), "measured_cases[2].occupants", "duplicate", "3 occupants", id="third-repeats-first"
        ),
    ],
)
def test_a_measured_case_for_an_impossible_or_repeated_occupant_count_is_refused(
    occupant_counts: tuple[int, ...], field: str, rule: str, words: str
) -> None:
    measured = tuple(MeasuredCase(n, wheels("173", "160", "170", "503")) for n in occupant_counts)
    with pytest.raises(StabilityError) as refused:
        assess(replace(PAPER_VEHICLE, measured_cases=measured))
    assert (refused.value.field, refused.value.rule) == (field, rule)
    assert words in refused.value.message
    assert field in str(refused.value)


@pytest.mark.parametrize(
    ("measured", "field", "rule", "words"),
    [
        pytest.param(
            (MeasuredCase(2, wheels("0", "160", "170")),),
            "measured_cases[0].readings.front_kg",
            "range",
            "more than 0",
            id="zero-front-reading",
        ),
        pytest.param(
            (MeasuredCase(1, wheels("175", "120", "136")), MeasuredCase(2, wheels("173", "NaN", "170"))),
            "measured_cases[1].readings.left_rear_kg",
            "finite",
            "finite number",
            id="nan-in-the-second-measured-case",
        ),
        pytest.param(
            (MeasuredCase(2, wheels("173", "160", "170", "520")),),
            "measured_cases[0].readings.overall_kg",
            "sum_tolerance",
            "add up to 503 kg but the overall weight is 520 kg; the difference (3.3 %)",
            id="wheel-sum-disagrees-with-overall-weight",
        ),
        pytest.param(
            # 1 + 250 + 250 = 501 is within 1 % of 497, but 497 - 500 = -3 kg would be left on the front wheel
            (MeasuredCase(3, wheels("1", "250", "250", "497")),),
            "measured_cases[0].readings",
            "front_wheel_lift",
            "3 occupant(s) the front wheel would carry -3 kg",
            id="front-wheel-lifts",
        ),
    ],
)
def test_a_measured_case_with_bad_readings_is_refused_under_its_own_name(
    measured: tuple[MeasuredCase, ...], field: str, rule: str, words: str
) -> None:
    with pytest.raises(StabilityError) as refused:
        assess(replace(PAPER_VEHICLE, measured_cases=measured))
    assert (refused.value.field, refused.value.rule) == (field, rule)
    assert words in refused.value.message


# ---------------------------------------------------------------------------------------------------------
# Load items: each adds m to the total and m * x / WB to the rear in every case (WB = 2 m here).


@pytest.mark.parametrize(
    ("items", "added_total", "added_rear", "verdict_line", "max_occupants"),
    [
        pytest.param(
            ((20, "2.5"),),
            20,
            Fraction(25),
            "NC NC NC NC NC",
            0,
            id="20-kg-behind-the-rear-axle-fails-the-driver",
        ),
        # 15 * 0.4 / 2 + 30 * 1.9 / 2 = 3 + 28.5; driver: 314.9908/476 < 2/3, +1: 373.6816/548 > 2/3
        pytest.param(
            ((15, "0.4"), (30, "1.9")), 45, Fraction("31.5"), "NC C NC NC NC", 1, id="two-items-add-up"
        ),
        # +1: 342.1816/513 > 342/513 = 2/3
        pytest.param(
            ((10, "0"),),
            10,
            Fraction(0),
            "NC C NC NC NC",
            1,
            id="at-the-front-wheel-centre-adds-no-rear-load",
        ),
        # 10 * -0.5 / 2 = -2.5; +1: 339.6816/513 < 2/3, +2: 398.3724/585 > 390/585
        pytest.param(
            ((10, "-0.5"),),
            10,
            Fraction("-2.5"),
            "NC C C NC NC",
            2,
            id="ahead-of-the-front-wheel-unloads-the-rear",
        ),
    ],
)
def test_load_items_add_their_mass_and_moment_to_every_case(
    items: tuple[tuple[int, str], ...],
    added_total: int,
    added_rear: Fraction,
    verdict_line: str,
    max_occupants: int,
) -> None:
    load_items = tuple(
        LoadItem(Decimal(mass), Decimal(x), label=f"item {i}") for i, (mass, x) in enumerate(items)
    )
    assessment = assess(replace(PAPER_VEHICLE, load_items=load_items))
    assert len(assessment.cases) == 5
    for case, total, rear in zip(assessment.cases, COMPUTED_TOTALS, COMPUTED_REARS, strict=True):
        assert case.total_kg == total + added_total
        assert case.rear_kg == rear + added_rear
    assert verdicts(assessment) == verdict_line
    assert assessment.max_compliant_occupants == max_occupants
