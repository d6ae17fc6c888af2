"""Sized remedies (LATERAL-STABILITY.md section 6): the reference's table, its summary, and edge cases.

Every figure is checked twice: against the reference's printed digits, and against an independent
computation in this file that never uses the closed forms of app/stability/remedies.py: it searches
the least advised step (0.01 kg, 0.001 m, 0.001) at which the case's own inequality holds, by
bisection on the loads themselves (ballast and seat shift) or on the understeer condition (tyres).
"""

from __future__ import annotations

from collections.abc import Callable
from decimal import Decimal
from fractions import Fraction

import pytest

from app.stability import (
    Assessment,
    AssessmentInput,
    LoadingCase,
    Seat,
    StabilityError,
    WheelReadings,
    assess,
)
from app.stability.remedies import advice, as_decimal, size_remedies

D = Decimal
WB = Fraction(2)
M_O = Fraction(72)


def vehicle(
    front: str, left: str, right: str, *, wheelbase: str = "2.000", seats: tuple[str, ...] = ("0.9303",)
) -> AssessmentInput:
    """One weighing of a vehicle with the driver's seat first and passengers after it."""
    layout = tuple(Seat("driver" if i == 0 else "passenger", D(x)) for i, x in enumerate(seats))
    return AssessmentInput(
        readings=WheelReadings((D(front),), (D(left),), (D(right),)), wheelbase_m=D(wheelbase), seats=layout
    )


STUDY = AssessmentInput(
    readings=WheelReadings((D("108"),), (D("115"),), (D("135"),), (D("359"),)),
    wheelbase_m=D("2.000"),
    seats=(Seat("driver", D("0.9303")), *(Seat("passenger", D("1.6303")),) * 3),
    occupant_mass_kg=D("72"),
)


@pytest.fixture(scope="module")
def study() -> Assessment:
    return assess(STUDY)


# --- the independent computation -------------------------------------------------------------------


def least_step(holds: Callable[[Fraction], bool], step: Fraction, ceiling: int = 10**7) -> Fraction:
    """The least n * step (n >= 0) at which `holds` is true, by bisection (holds is monotone)."""
    low, high = 0, ceiling
    assert holds(high * step)
    while low < high:
        middle = (low + high) // 2
        if holds(middle * step):
            high = middle
        else:
            low = middle + 1
    return low * step


def ballast_by_search(total: Fraction, rear: Fraction, x_b: Fraction) -> Fraction:
    """Least 0.01 kg of ballast at x_b after which the rear carries less than 2/3 of the weight."""
    return least_step(lambda m: 3 * (rear + m * x_b / WB) < 2 * (total + m), Fraction(1, 100))


def shift_by_search(total: Fraction, rear: Fraction, passengers: int) -> Fraction:
    """Least 0.001 m of forward seat travel after which the case complies."""
    return least_step(lambda d: 3 * (rear - passengers * M_O * d / WB) < 2 * total, Fraction(1, 1000))


def ratio_by_search(total: Fraction, rear: Fraction) -> Fraction:
    """Least 0.001 ratio CaR/CaF with 2 L2 CaR > L1 CaF (paper eq. 23, tyres differing front and rear)."""
    l1 = WB * rear / total
    l2 = WB - l1
    return least_step(lambda k: 2 * l2 * k > l1, Fraction(1, 1000))


# --- the reference's table -------------------------------------------------------------------------

# occupants, 3R - 2W, ballast at 0.30 m, at -0.20 m, seats forward, CaR/CaF, exactly as printed; None: "-".
TABLE = [
    pytest.param(0, "32.00", "20.65", "13.91", "impossible", "1.1468", id="none"),
    pytest.param(1, "-11.53", None, None, None, "0.9609", id="driver"),
    pytest.param(2, "20.54", "13.25", "8.93", "0.1902", "1.0639", id="driver+1"),
    pytest.param(3, "52.62", "33.95", "22.88", "0.2436", "1.1511", id="driver+2"),
    pytest.param(4, "84.69", "54.64", "36.82", "0.2614", "1.2259", id="driver+3"),
]
# The exact totals and rear loads of the study's cases (reference section 3), for the search.
LOADS = {0: ("359", "250"), 1: ("431", "283.4908"), 2: ("503", "342.1816"), 3: ("575", "400.8724")}
LOADS[4] = ("647", "459.5632")


@pytest.mark.parametrize(("occupants", "excess", "at_030", "at_m020", "shift", "ratio"), TABLE)
def test_each_case_matches_the_reference_table_and_the_search(
    study: Assessment,
    occupants: int,
    excess: str,
    at_030: str | None,
    at_m020: str | None,
    shift: str | None,
    ratio: str,
) -> None:
    total, rear = (Fraction(v) for v in LOADS[occupants])
    behind = size_remedies(study, ballast_x_m=D("0.30")).cases[occupants]
    ahead = size_remedies(study, ballast_x_m=D("-0.20")).cases[occupants]
    assert behind.occupants == occupants
    assert round(behind.excess_kg, 2) == Fraction(excess)
    assert round(behind.tyre_ratio, 4) == Fraction(ratio)
    assert advice(behind.tyre_ratio, Fraction(1, 1000)) == ratio_by_search(total, rear)
    if at_030 is None:
        assert behind.compliant
        assert behind.ballast_kg is None
        assert behind.seat_shift_m is None
        return
    assert behind.ballast_kg is not None
    assert ahead.ballast_kg is not None
    assert round(behind.ballast_kg, 2) == Fraction(at_030)
    assert round(ahead.ballast_kg, 2) == Fraction(str(at_m020))
    assert advice(behind.ballast_kg, Fraction(1, 100)) == ballast_by_search(total, rear, Fraction("0.30"))
    assert advice(ahead.ballast_kg, Fraction(1, 100)) == ballast_by_search(total, rear, Fraction("-0.20"))
    if shift == "impossible":
        assert behind.seat_shift_m is None
        assert not behind.fixable_by_seat_shift
    else:
        assert behind.seat_shift_m is not None
        assert shift is not None
        assert round(behind.seat_shift_m, 4) == Fraction(shift)
        assert advice(behind.seat_shift_m, Fraction(1, 1000)) == shift_by_search(total, rear, occupants - 1)


def test_the_summary_sentence_figures(study: Assessment) -> None:
    """'more than 54.64 kg at 0.30 m (or 36.82 kg at 0.20 m ahead); the rear bench 0.27 m forward, but
    not the empty vehicle; rear tyres at least 1.226 times as stiff'."""
    behind = size_remedies(study)
    ahead = size_remedies(study, ballast_x_m=D("-0.20"))
    assert behind.target_occupants == 4
    assert not behind.compliant
    assert behind.max_compliant_occupants == 1
    assert behind.ballast is not None
    assert behind.ballast.bound is not None
    assert behind.ballast.binding_occupants == 4
    assert behind.ballast.possible
    assert as_decimal(behind.ballast.advised or Fraction(0), Fraction(1, 100)) == D("54.64")
    assert ahead.ballast is not None
    assert ahead.ballast.bound is not None
    assert round(ahead.ballast.bound, 2) == Fraction("36.82")
    # 36.8216 kg exactly: the advice rounds up so that it suffices on its own.
    assert (
        ahead.ballast.advised
        == Fraction("36.83")
        == ballast_by_search(Fraction(647), Fraction("459.5632"), Fraction("-0.2"))
    )
    shift = behind.seat_shift
    assert shift is not None
    assert shift.bound is not None
    assert advice(shift.bound, Fraction(1, 100)) == Fraction("0.27")  # the summary's 0.27 m
    assert shift.advised == Fraction("0.262")
    assert shift.binding_occupants == 4
    assert not shift.possible
    assert shift.unfixable_occupants == (0,)
    tyres = behind.rear_tyre_ratio
    assert tyres is not None
    assert tyres.advised == Fraction("1.226")
    assert tyres.binding_occupants == 4


def test_after_each_remedy_every_mended_case_complies(study: Assessment) -> None:
    result = size_remedies(study)
    for case in result.cases:
        assert case.lsf_after_ballast is not None
        assert case.lsf_after_ballast < Fraction(2, 3)
        assert case.lsf_after_seat_shift is not None
        # The empty vehicle and the driver alone keep their LSF: no passenger seat moves.
        if case.occupants <= 1:
            assert case.lsf_after_seat_shift == case.lsf
        else:
            assert case.lsf_after_seat_shift < Fraction(2, 3)
    assert result.cases[0].lsf_after_seat_shift == Fraction(250, 359)  # still non-compliant


# --- edge cases -------------------------------------------------------------------------------------


def test_a_compliant_vehicle_needs_no_remedy() -> None:
    result = size_remedies(assess(vehicle("200", "100", "100", seats=("0.9", "1.2", "1.2"))))
    assert result.compliant
    assert result.ballast is None
    assert result.seat_shift is None
    assert result.rear_tyre_ratio is None
    assert all(c.ballast_kg is None and c.seat_shift_m is None for c in result.cases)
    assert all(c.lsf_after_ballast is None and c.lsf_after_seat_shift is None for c in result.cases)


@pytest.mark.parametrize(
    "x_b", ["1.3334", "1.5", "2.0", "3.0"], ids=["just-behind-2/3", "1.5", "axle", "3.0"]
)
def test_ballast_at_or_behind_two_thirds_of_the_wheelbase_cannot_help(study: Assessment, x_b: str) -> None:
    result = size_remedies(study, ballast_x_m=D(x_b))
    assert result.ballast is not None
    assert not result.ballast.possible
    assert result.ballast.advised is None
    assert result.ballast.binding_occupants is None
    assert result.ballast.unfixable_occupants == (0, 2, 3, 4)


def test_ballast_exactly_at_two_thirds_of_the_wheelbase_cannot_help() -> None:
    result = size_remedies(assess(vehicle("100", "100", "110", wheelbase="3.000")), ballast_x_m=D("2.0"))
    assert result.ballast is not None
    assert result.ballast.unfixable_occupants == (0,)


def test_the_empty_case_cannot_be_mended_by_moving_seats(study: Assessment) -> None:
    result = size_remedies(study, target_occupants=0)
    assert result.target_occupants == 0
    assert [c.occupants for c in result.cases] == [0]
    assert result.seat_shift is not None
    assert result.seat_shift.advised is None
    assert result.seat_shift.unfixable_occupants == (0,)
    assert not result.seat_shift.possible


@pytest.mark.parametrize("target", [5, 12, -1])
def test_a_target_outside_the_seats_is_refused(study: Assessment, target: int) -> None:
    with pytest.raises(StabilityError) as refused:
        size_remedies(study, target_occupants=target)
    assert refused.value.field == "target_occupants"
    assert refused.value.rule == "range"
    assert "4 seat(s)" in refused.value.message


@pytest.mark.parametrize("x_b", ["-1.5", "3.0001", "0.12345"])
def test_a_ballast_position_out_of_reach_or_too_precise_is_refused(study: Assessment, x_b: str) -> None:
    with pytest.raises(StabilityError) as refused:
        size_remedies(study, ballast_x_m=D(x_b))
    assert refused.value.field == "ballast_x_m"


def test_a_lower_target_sizes_only_the_cases_up_to_it(study: Assessment) -> None:
    result = size_remedies(study, target_occupants=2)
    assert [c.occupants for c in result.cases] == [0, 1, 2]
    assert result.ballast is not None
    assert result.ballast.binding_occupants == 0
    assert result.ballast.advised == Fraction("20.65")
    assert result.seat_shift is not None
    assert result.seat_shift.advised == Fraction("0.191")


def test_an_exact_boundary_is_advised_one_step_above() -> None:
    """W = 400, R = 280: 3R - 2W = 40 kg; at x_b = 0 exactly 20.00 kg leaves LSF = 2/3, so 20.01 kg."""
    result = size_remedies(assess(vehicle("120", "140", "140")), target_occupants=0, ballast_x_m=D("0"))
    assert result.ballast is not None
    assert result.ballast.bound == 20
    assert (
        result.ballast.advised
        == Fraction("20.01")
        == ballast_by_search(Fraction(400), Fraction(280), Fraction(0))
    )
    assert result.cases[0].lsf_after_ballast is not None
    assert result.cases[0].lsf_after_ballast < Fraction(2, 3)
    # The tyre ratio at LSF 0.7: 280 / 240 = 7/6 = 1.1666..., advised 1.167.
    assert result.rear_tyre_ratio is not None
    assert result.rear_tyre_ratio.advised == Fraction("1.167")


def test_exactly_two_thirds_needs_a_ratio_above_one() -> None:
    """a = 103.2, b = 91.3, c = 115.1 gives exactly 2/3 (reference section 2): the factor is 1, so 1.001."""
    result = size_remedies(assess(vehicle("103.2", "91.3", "115.1")), target_occupants=0)
    assert result.cases[0].tyre_ratio == 1
    assert result.cases[0].excess_kg == 0
    assert result.rear_tyre_ratio is not None
    assert result.rear_tyre_ratio.advised == Fraction("1.001")
    assert result.ballast is not None
    assert result.ballast.bound == 0
    assert result.ballast.advised == Fraction("0.01")


# Vehicles of our own: front, left, right (kg), seats; target, advised ballast at 0.30 m, seat shift
# (None: no case with passengers fails), ratio, and the cases seat shifts cannot mend.
OWN_VEHICLES = [
    pytest.param(
        ("90", "120", "130"), ("1.0", "1.7", "1.7"), (3, "73.04", "0.682", "1.389", (0, 1)), id="rear-heavy"
    ),
    pytest.param(
        ("150", "100", "110"),
        ("0.9", "1.9", "1.9", "1.9", "1.9"),
        (5, "69.68", "0.251", "1.265", ()),
        id="long-bench",
    ),
    pytest.param(
        ("118", "118", "122"), ("0.9", "1.6"), (2, "2.59", None, "1.017", (0,)), id="only-empty-fails"
    ),
]


@pytest.mark.parametrize(("wheels", "seats", "expected"), OWN_VEHICLES)
def test_vehicles_of_our_own_agree_with_the_search(
    wheels: tuple[str, str, str],
    seats: tuple[str, ...],
    expected: tuple[int, str, str | None, str, tuple[int, ...]],
) -> None:
    target, ballast, shift, ratio, unfixable = expected
    assessment = assess(vehicle(*wheels, seats=seats))
    result = size_remedies(assessment)
    assert result.target_occupants == target
    assert not result.compliant
    assert result.ballast is not None
    assert result.seat_shift is not None
    assert result.rear_tyre_ratio is not None
    assert result.ballast.advised == Fraction(ballast)
    assert result.rear_tyre_ratio.advised == Fraction(ratio)
    assert result.seat_shift.unfixable_occupants == unfixable
    cases: list[LoadingCase] = list(assessment.cases)
    failing = [c for c in cases if not c.compliant]
    assert result.ballast.advised == max(
        ballast_by_search(c.total_kg, c.rear_kg, Fraction("0.30")) for c in failing
    )
    assert result.rear_tyre_ratio.advised == max(ratio_by_search(c.total_kg, c.rear_kg) for c in cases)
    mended = [shift_by_search(c.total_kg, c.rear_kg, c.occupants - 1) for c in failing if c.occupants > 1]
    if shift is None:
        assert result.seat_shift.advised is None
        assert not mended
    else:
        assert result.seat_shift.advised == Fraction(shift) == max(mended)
