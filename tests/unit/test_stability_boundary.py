"""The 2/3 boundary: exactly 2/3 is non-compliant, decided in exact arithmetic, never in binary floats."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import pytest

from app.stability import LSF_LIMIT, AssessmentInput, LoadingCase, Seat, WheelReadings, assess


def empty_case(front: str, left: str, right: str) -> LoadingCase:
    """The empty-vehicle case of a driver-only vehicle weighed without an overall reading."""
    data = AssessmentInput(
        readings=WheelReadings((Decimal(front),), (Decimal(left),), (Decimal(right),)),
        wheelbase_m=Decimal("2.000"),
        seats=(Seat("driver", Decimal("1.0")),),
    )
    return assess(data).cases[0]


def test_the_limit_is_exactly_two_thirds() -> None:
    assert Fraction(2, 3) == LSF_LIMIT


@pytest.mark.parametrize(
    ("total", "rear", "compliant"),
    [
        pytest.param(Fraction(300), Fraction(200), False, id="exactly-2/3-NC"),
        pytest.param(Fraction(3), Fraction(2) - Fraction(1, 10**30), True, id="a-hair-below-2/3-C"),
        pytest.param(Fraction(3), Fraction(2) + Fraction(1, 10**30), False, id="a-hair-above-2/3-NC"),
        pytest.param(Fraction(3), Fraction(1), True, id="one-third-C"),
    ],
)
def test_a_loading_case_complies_only_strictly_below_two_thirds(
    total: Fraction, rear: Fraction, compliant: bool
) -> None:
    case = LoadingCase(occupants=0, total_kg=total, rear_kg=rear)
    assert case.compliant is compliant
    assert (case.variance > 0) is compliant


def test_exactly_two_thirds_is_not_compliant() -> None:
    case = empty_case("100", "100", "100")
    assert case.lsf == Fraction(2, 3)
    assert case.variance == 0
    assert case.compliant is False


# a + b + c = 309.6 and b + c = 206.4 = 2/3 * 309.6 exactly.
@pytest.mark.parametrize(
    ("front", "left", "right", "lsf", "compliant"),
    [
        pytest.param("100", "100", "100", Fraction(2, 3), False, id="round-numbers-exactly-2/3-NC"),
        pytest.param("103.2", "91.3", "115.1", Fraction(2, 3), False, id="float-trap-exactly-2/3-NC"),
        pytest.param(
            "100.001", "100", "100", Fraction(200_000, 300_001), True, id="one-gram-lighter-rear-share-C"
        ),
        pytest.param(
            "99.999", "100", "100", Fraction(200_000, 299_999), False, id="one-gram-heavier-rear-share-NC"
        ),
        pytest.param(
            "103.201", "91.3", "115.1", Fraction(206_400, 309_601), True, id="float-trap-plus-one-gram-C"
        ),
    ],
)
def test_the_verdict_at_the_boundary_is_exact(
    front: str, left: str, right: str, lsf: Fraction, compliant: bool
) -> None:
    case = empty_case(front, left, right)
    assert case.lsf == lsf
    assert case.compliant is compliant


def test_the_float_trap_is_exactly_two_thirds_and_non_compliant_although_floats_would_pass_it() -> None:
    naive = (91.3 + 115.1) / (103.2 + 91.3 + 115.1)
    assert naive == 0.6666666666666665
    assert naive < 2 / 3  # the float comparison would wrongly certify the vehicle
    case = empty_case("103.2", "91.3", "115.1")
    assert case.lsf == Fraction(2, 3)
    assert case.compliant is False


def test_a_vehicle_at_exactly_two_thirds_empty_is_non_compliant_overall() -> None:
    data = AssessmentInput(
        readings=WheelReadings((Decimal("103.2"),), (Decimal("91.3"),), (Decimal("115.1"),)),
        wheelbase_m=Decimal("2.000"),
        # 72 * 0.5 / 2 = 18 kg to the rear: (206.4 + 18) / (309.6 + 72) = 224.4 / 381.6 < 2/3
        seats=(Seat("driver", Decimal("0.5")),),
    )
    assessment = assess(data)
    assert [case.compliant for case in assessment.cases] == [False, True]
    assert assessment.cases[1].lsf == Fraction("224.4") / Fraction("381.6")
    assert assessment.compliant is False
    assert assessment.max_compliant_occupants == 1
