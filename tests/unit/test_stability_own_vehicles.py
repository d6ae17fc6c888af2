"""Vehicles invented for these tests, their figures worked out by hand in exact fractions.

Also the semantics of max_compliant_occupants and of the standard occupant mass.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import pytest

from app.stability import Assessment, AssessmentInput, Rules, Seat, WheelReadings, assess


def wheels(front: str, left: str, right: str, overall: str | None = None) -> WheelReadings:
    return WheelReadings(
        (Decimal(front),),
        (Decimal(left),),
        (Decimal(right),),
        (Decimal(overall),) if overall is not None else (),
    )


def seats(driver: str, *passengers: str) -> tuple[Seat, ...]:
    return (Seat("driver", Decimal(driver)), *(Seat("passenger", Decimal(x)) for x in passengers))


# A well-balanced keke: a = 150, b = 100, c = 110, W = 360 (= a + b + c), WB = 2.4 m, occupant mass 75 kg,
# driver at 0.96 m, two passengers at 1.44 m.
#   empty      W = 360, R = 210                     LSF = 210/360 = 7/12    variance = 2/3 - 7/12  = 1/12
#   driver     +75, +75 * 0.96 / 2.4 = +30  -> 435, 240   LSF = 16/29       variance = (58 - 48)/87 = 10/87
#   + 1        +75, +75 * 1.44 / 2.4 = +45  -> 510, 285   LSF = 19/34       variance = (68 - 57)/102 = 11/102
#   + 2        +75, +45                     -> 585, 330   LSF = 22/39       variance = (26 - 22)/39 = 4/39
#   CG behind the front wheel: 2.4 * 210 / 360 = 7/5 m
BALANCED = AssessmentInput(
    readings=wheels("150", "100", "110", "360"),
    wheelbase_m=Decimal("2.4"),
    seats=seats("0.96", "1.44", "1.44"),
    occupant_mass_kg=Decimal("75"),
)


@pytest.fixture(scope="module")
def balanced() -> Assessment:
    return assess(BALANCED)


@pytest.mark.parametrize(
    ("occupants", "total", "rear", "lsf", "variance"),
    [
        pytest.param(0, 360, 210, Fraction(7, 12), Fraction(1, 12), id="empty"),
        pytest.param(1, 435, 240, Fraction(16, 29), Fraction(10, 87), id="driver"),
        pytest.param(2, 510, 285, Fraction(19, 34), Fraction(11, 102), id="driver+1"),
        pytest.param(3, 585, 330, Fraction(22, 39), Fraction(4, 39), id="driver+2"),
    ],
)
def test_a_balanced_vehicle_matches_its_hand_worked_figures(
    balanced: Assessment, occupants: int, total: int, rear: int, lsf: Fraction, variance: Fraction
) -> None:
    case = balanced.cases[occupants]
    assert case.occupants == occupants
    assert case.total_kg == total
    assert case.rear_kg == rear
    assert case.front_kg == total - rear
    assert case.lsf == lsf
    assert case.variance == variance
    assert case.compliant is True


def test_a_vehicle_compliant_in_every_case_may_carry_every_seat(balanced: Assessment) -> None:
    assert len(balanced.cases) == len(BALANCED.seats) + 1
    assert balanced.compliant is True
    assert balanced.max_compliant_occupants == len(BALANCED.seats) == 3


def test_the_balanced_vehicles_centre_of_gravity_is_1_4_m_behind_the_front_wheel(
    balanced: Assessment,
) -> None:
    assert balanced.cg_from_front_m == Fraction(7, 5)


@pytest.mark.parametrize(
    ("occupant_mass", "rules", "mass_used", "driver_rear"),
    [
        # 210 + 72 * 0.96 / 2.4 = 210 + 28.8
        pytest.param(
            None, None, Decimal("72"), Fraction("238.8"), id="no-mass-given-uses-the-standard-72-kg"
        ),
        # 210 + 80 * 0.96 / 2.4 = 210 + 32
        pytest.param(
            None,
            Rules(occupant_mass_kg=Decimal("80")),
            Decimal("80"),
            Fraction(242),
            id="regulator-set-80-kg",
        ),
        # the input's own mass wins over the rules: 210 + 75 * 0.4 = 240
        pytest.param(
            Decimal("75"),
            Rules(occupant_mass_kg=Decimal("80")),
            Decimal("75"),
            Fraction(240),
            id="input-mass-wins",
        ),
    ],
)
def test_the_occupant_mass_comes_from_the_input_else_from_the_rules(
    occupant_mass: Decimal | None, rules: Rules | None, mass_used: Decimal, driver_rear: Fraction
) -> None:
    data = AssessmentInput(
        readings=BALANCED.readings,
        wheelbase_m=BALANCED.wheelbase_m,
        seats=BALANCED.seats,
        occupant_mass_kg=occupant_mass,
    )
    assessment = assess(data, rules)
    assert assessment.occupant_mass_kg == mass_used
    assert assessment.cases[1].total_kg == 360 + Fraction(mass_used)
    assert assessment.cases[1].rear_kg == driver_rear


# max_compliant_occupants: the largest k such that every case with 1..k occupants complies. WB = 2 m, 72 kg.
# Vehicle H (rear-heavy): a = 100, b = c = 110, no overall weight: W = 320, R = 220, LSF = 11/16 (NC).
# Vehicle L (light rear): a = 150, b = 100, c = 110, no overall weight: W = 360, R = 210, LSF = 7/12 (C).
# An occupant at x adds 72 * x / 2 = 36 x kg to the rear.
@pytest.mark.parametrize(
    ("readings", "layout", "lsfs", "max_occupants", "compliant"),
    [
        pytest.param(
            # driver at 1.6: 277.6/392; passenger at -0.5: 259.6/464 passes, but too late
            wheels("100", "110", "110"),
            seats("1.6", "-0.5"),
            [Fraction(11, 16), Fraction(347, 490), Fraction(649, 1160)],
            0,
            False,
            id="driver-alone-fails-gives-0-even-if-a-passenger-restores-it",
        ),
        pytest.param(
            # driver at 0.4: 234.4/392; passenger at 0.8: 263.2/464
            wheels("100", "110", "110"),
            seats("0.4", "0.8"),
            [Fraction(11, 16), Fraction(293, 490), Fraction(329, 580)],
            2,
            False,
            id="empty-vehicle-NC-does-not-reduce-it",
        ),
        pytest.param(
            # driver at 0.8: 238.8/432; passenger at 3.0: 346.8/504 fails; passenger at -1.0: 310.8/576 passes
            wheels("150", "100", "110"),
            seats("0.8", "3.0", "-1.0"),
            [Fraction(7, 12), Fraction(199, 360), Fraction(289, 420), Fraction(259, 480)],
            1,
            False,
            id="stops-at-the-first-failing-occupied-case-even-if-a-later-one-passes",
        ),
        pytest.param(
            # driver at 0.8: 238.8/432; passenger at 1.2: 282/504
            wheels("150", "100", "110"),
            seats("0.8", "1.2"),
            [Fraction(7, 12), Fraction(199, 360), Fraction(47, 84)],
            2,
            True,
            id="all-compliant-gives-the-seat-count",
        ),
    ],
)
def test_max_compliant_occupants_counts_the_leading_run_of_compliant_occupied_cases(
    readings: WheelReadings,
    layout: tuple[Seat, ...],
    lsfs: list[Fraction],
    max_occupants: int,
    compliant: bool,
) -> None:
    assessment = assess(
        AssessmentInput(
            readings=readings, wheelbase_m=Decimal("2.000"), seats=layout, occupant_mass_kg=Decimal("72")
        )
    )
    assert [case.lsf for case in assessment.cases] == lsfs
    assert [case.compliant for case in assessment.cases] == [lsf < Fraction(2, 3) for lsf in lsfs]
    assert assessment.max_compliant_occupants == max_occupants
    assert assessment.compliant is compliant
