"""The general core of reference section 9: delta, tadpole and quadricycle through one rule.

Each figure is checked against the reference's table and against a computation written here, apart
from the core: each rear tyre carries less than each front tyre, R / n_r < F / n_f.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import pytest

from app.stability import (
    DELTA,
    LAYOUTS,
    QUADRICYCLE,
    RULES_VERSION,
    TADPOLE,
    AssessmentInput,
    Layout,
    MeasuredCase,
    Seat,
    StabilityError,
    WheelReadings,
    assess,
    layout_named,
    rules_version,
)
from app.stability.dynamics import critical_speed_ms, rollover_threshold_about_axis, understeer_margin
from app.stability.remedies import advice_of, size_remedies


def kg(*values: str) -> tuple[Decimal, ...]:
    return tuple(Decimal(v) for v in values)


TADPOLE_SEATS = (Seat("driver", Decimal("0.700")), *(Seat("passenger", Decimal("1.350")),) * 3)
TADPOLE_EXAMPLE = AssessmentInput(
    readings=WheelReadings(left_front_kg=kg("186"), right_front_kg=kg("182"), rear_kg=kg("112")),
    wheelbase_m=Decimal("1.900"),
    seats=TADPOLE_SEATS,
    occupant_mass_kg=Decimal("72"),
    layout=TADPOLE,
)

# Reference section 9, the worked tadpole: total, rear, LSF, variance 1/3 - LSF, verdict, exact LSF.
TADPOLE_TABLE = [
    (0, "480.0", "112.00", "0.2333", "+0.1000", True, Fraction(7, 30)),
    (1, "552.0", "138.53", "0.2510", "+0.0824", True, Fraction(329, 1311)),
    (2, "624.0", "189.68", "0.3040", "+0.0294", True, Fraction(901, 2964)),
    (3, "696.0", "240.84", "0.3460", "-0.0127", False, Fraction(572, 1653)),
    (4, "768.0", "292.00", "0.3802", "-0.0469", False, Fraction(73, 192)),
]


def fixed(value: Fraction, places: int, *, sign: bool = False) -> str:
    return f"{float(value):+.{places}f}" if sign else f"{float(value):.{places}f}"


def separately(
    front: Fraction, rear: Fraction, n_f: int, n_r: int, seats: tuple[Seat, ...], mass: Fraction, wb: Fraction
) -> list[tuple[Fraction, Fraction, bool]]:
    """The loading cases by hand: moments about the front axle, the per-tyre rule, no LSF limit."""
    rows = [(front + rear, rear, rear / n_r < front / n_f)]
    for seat in seats:
        share = mass * Fraction(seat.x_m) / wb
        rear += share
        front += mass - share
        rows.append((front + rear, rear, rear / n_r < front / n_f))
    return rows


def test_the_layouts_have_the_reference_s_tyre_counts_limits_and_readings() -> None:
    assert [(name, lay.n_front, lay.n_rear, lay.limit) for name, lay in LAYOUTS.items()] == [
        ("delta", 1, 2, Fraction(2, 3)),
        ("tadpole", 2, 1, Fraction(1, 3)),
        ("quadricycle", 2, 2, Fraction(1, 2)),
    ]
    assert DELTA.wheels == ("front_kg", "left_rear_kg", "right_rear_kg")
    assert TADPOLE.wheels == ("left_front_kg", "right_front_kg", "rear_kg")
    assert QUADRICYCLE.wheels == ("left_front_kg", "right_front_kg", "left_rear_kg", "right_rear_kg")
    # The delta's rules version is the one every stored inspection already carries.
    assert rules_version(DELTA) == RULES_VERSION == "lsf<2/3:cumulative-cases:v1"
    assert rules_version(TADPOLE) == "lsf<1/3:cumulative-cases:v1"
    assert rules_version(QUADRICYCLE) == "lsf<1/2:cumulative-cases:v1"


@pytest.mark.parametrize(
    ("occupants", "total", "rear", "lsf", "variance", "compliant", "exact"), TADPOLE_TABLE
)
def test_the_worked_tadpole_reproduces_to_the_digit(
    occupants: int, total: str, rear: str, lsf: str, variance: str, compliant: bool, exact: Fraction
) -> None:
    case = assess(TADPOLE_EXAMPLE).cases[occupants]
    assert (fixed(case.total_kg, 1), fixed(case.rear_kg, 2)) == (total, rear)
    assert (fixed(case.lsf, 4), fixed(case.variance, 4, sign=True)) == (lsf, variance)
    assert case.compliant is compliant
    assert case.lsf == exact
    assert case.limit == Fraction(1, 3)


def test_the_worked_tadpole_agrees_with_the_separate_computation_and_is_certified_for_two() -> None:
    result = assess(TADPOLE_EXAMPLE)
    by_hand = separately(Fraction(368), Fraction(112), 2, 1, TADPOLE_SEATS, Fraction(72), Fraction("1.9"))
    assert [(c.total_kg, c.rear_kg, c.compliant) for c in result.cases] == by_hand
    assert result.max_compliant_occupants == 2  # the driver and one passenger
    assert result.compliant is False
    assert result.readings.front_kg == 368
    assert result.readings.rear_kg == 112


def test_the_worked_tadpole_s_remedies_are_the_reference_s() -> None:
    advice = advice_of(size_remedies(assess(TADPOLE_EXAMPLE), ballast_x_m=Decimal("0.20")))
    remedies = size_remedies(assess(TADPOLE_EXAMPLE), ballast_x_m=Decimal("0.20"))
    assert remedies.ballast is not None
    assert remedies.seat_shift is not None
    assert remedies.rear_tyre_ratio is not None
    # By hand, the binding case (driver + 3): R - W/3 = 292 - 256 = 36 kg.
    assert remedies.ballast.bound == Fraction(36) / (Fraction(1, 3) - Fraction("0.2") / Fraction("1.9"))
    assert remedies.seat_shift.bound == Fraction(36) * Fraction("1.9") / (3 * 72)
    assert remedies.rear_tyre_ratio.bound == Fraction(2 * 292, 1 * 476)
    assert f"{float(remedies.ballast.bound):.2f}" == "157.85"
    assert f"{float(remedies.seat_shift.bound):.4f}" == "0.3167"
    assert f"{float(remedies.rear_tyre_ratio.bound):.4f}" == "1.2269"
    assert advice.ballast_kg == Decimal("157.85")
    assert advice.seat_shift_m == Decimal("0.317")


QUADRICYCLE_SEATS = (
    Seat("driver", Decimal("1.000")),
    Seat("passenger", Decimal("1.800")),
    Seat("passenger", Decimal("1.800")),
)


def test_a_quadricycle_agrees_with_the_separate_computation() -> None:
    data = AssessmentInput(
        readings=WheelReadings(
            left_front_kg=kg("150", "152"),
            right_front_kg=kg("148"),
            left_rear_kg=kg("140"),
            right_rear_kg=kg("143"),
            overall_kg=kg("582"),
        ),
        wheelbase_m=Decimal("2.000"),
        seats=QUADRICYCLE_SEATS,
        layout=QUADRICYCLE,
    )
    result = assess(data)
    by_hand = separately(Fraction(299), Fraction(283), 2, 2, QUADRICYCLE_SEATS, Fraction(72), Fraction(2))
    # The overall reading (582) stands for the total; the case's rear loads are those by hand.
    assert [(c.rear_kg, c.compliant) for c in result.cases] == [(r, ok) for _, r, ok in by_hand]
    assert [c.total_kg for c in result.cases] == [582 + 72 * k for k in range(4)]
    assert [c.limit for c in result.cases] == [Fraction(1, 2)] * 4


def test_a_tadpole_exactly_at_one_third_is_non_compliant_though_floats_say_otherwise() -> None:
    front_left, front_right, rear = 94.4, 106.2, 100.3
    assert rear / (front_left + front_right + rear) < 1 / 3  # the trap: floats would pass it
    data = AssessmentInput(
        readings=WheelReadings(left_front_kg=kg("94.4"), right_front_kg=kg("106.2"), rear_kg=kg("100.3")),
        wheelbase_m=Decimal("1.900"),
        seats=TADPOLE_SEATS[:1],
        layout=TADPOLE,
    )
    empty = assess(data).cases[0]
    assert empty.lsf == Fraction(1, 3)
    assert empty.compliant is False
    assert empty.variance == 0


def test_a_quadricycle_exactly_at_one_half_is_non_compliant_though_floats_say_otherwise() -> None:
    values = (88.8, 96.3, 90.0, 95.1)
    assert (values[2] + values[3]) / sum(values) < 1 / 2  # the trap
    data = AssessmentInput(
        readings=WheelReadings(
            left_front_kg=kg("88.8"),
            right_front_kg=kg("96.3"),
            left_rear_kg=kg("90.0"),
            right_rear_kg=kg("95.1"),
        ),
        wheelbase_m=Decimal("2.000"),
        seats=QUADRICYCLE_SEATS[:1],
        layout=QUADRICYCLE,
    )
    empty = assess(data).cases[0]
    assert empty.lsf == Fraction(1, 2)
    assert empty.compliant is False


def test_a_measured_case_is_read_with_the_layout_s_wheels() -> None:
    measured = MeasuredCase(
        1, WheelReadings(left_front_kg=kg("200"), right_front_kg=kg("196"), rear_kg=kg("150"))
    )
    result = assess(AssessmentInput(**{**TADPOLE_EXAMPLE.__dict__, "measured_cases": (measured,)}))
    case = result.cases[1]
    assert case.measured
    assert case.rear_kg == 150
    assert case.total_kg == 546
    assert case.lsf == Fraction(150, 546)
    assert case.compliant


@pytest.mark.parametrize(
    ("layout", "readings", "field", "words"),
    [
        (
            TADPOLE,
            WheelReadings(
                front_kg=kg("100"), left_front_kg=kg("186"), right_front_kg=kg("182"), rear_kg=kg("112")
            ),
            "readings.front_kg",
            "readings.front_kg: not a reading of a tadpole vehicle (two front wheels and one rear wheel); "
            "give left_front_kg, right_front_kg, rear_kg",
        ),
        (
            DELTA,
            WheelReadings(kg("108"), kg("115"), kg("135"), rear_kg=kg("250")),
            "readings.rear_kg",
            "readings.rear_kg: not a reading of a delta vehicle",
        ),
        (
            QUADRICYCLE,
            WheelReadings(left_front_kg=kg("150"), right_front_kg=kg("148"), left_rear_kg=kg("140")),
            "readings.right_rear_kg",
            "readings.right_rear_kg: give at least one reading of the right rear wheel reaction",
        ),
    ],
)
def test_a_reading_of_another_layout_or_a_missing_wheel_is_refused_by_name(
    layout: Layout, readings: WheelReadings, field: str, words: str
) -> None:
    with pytest.raises(StabilityError) as refused:
        assess(
            AssessmentInput(
                readings=readings, wheelbase_m=Decimal("2.0"), seats=QUADRICYCLE_SEATS, layout=layout
            )
        )
    assert refused.value.field == field
    assert words in refused.value.message


def test_the_sum_check_counts_the_layout_s_wheels() -> None:
    readings = WheelReadings(
        left_front_kg=kg("150"),
        right_front_kg=kg("148"),
        left_rear_kg=kg("140"),
        right_rear_kg=kg("143"),
        overall_kg=kg("600"),
    )
    with pytest.raises(StabilityError) as refused:
        assess(
            AssessmentInput(
                readings=readings, wheelbase_m=Decimal("2.0"), seats=QUADRICYCLE_SEATS, layout=QUADRICYCLE
            )
        )
    assert refused.value.rule == "sum_tolerance"
    assert refused.value.message.startswith(
        "The four wheel readings add up to 581 kg but the overall weight is 600 kg"
    )


def test_an_unknown_layout_is_refused_naming_the_choices() -> None:
    with pytest.raises(StabilityError) as refused:
        layout_named("sidecar")
    assert refused.value.field == "layout"
    assert refused.value.rule == "unknown_layout"
    assert (
        refused.value.message
        == "layout: 'sidecar' is not an axle layout; choose one of delta, tadpole, quadricycle"
    )
    assert layout_named("tadpole") is TADPOLE


# ---- beyond the static test (reference section 9): each formula against one written here ----------

C = 8000.0  # N/rad per tyre, the reference's illustrative figure


@pytest.mark.parametrize(
    ("layout", "lsf"), [(DELTA, 0.71), (TADPOLE, 0.38), (QUADRICYCLE, 0.55), (TADPOLE, 0.25)]
)
def test_the_critical_speed_follows_the_layout_s_tyre_counts(layout: Layout, lsf: float) -> None:
    wb, mass = 1.9, 768.0
    l1, l2 = wb * lsf, wb * (1 - lsf)
    by_hand = layout.n_rear * l2 * C - layout.n_front * l1 * C
    margin = understeer_margin(
        wheelbase_m=wb,
        lsf=lsf,
        front_n_per_rad=C,
        rear_n_per_rad=C,
        n_front=layout.n_front,
        n_rear=layout.n_rear,
    )
    assert margin == pytest.approx(by_hand)
    # Identical tyres: S = C WB (n_r - (n_f + n_r) LSF), negative exactly above the static limit.
    assert (margin < 0) == (lsf > float(layout.limit))
    speed = critical_speed_ms(
        wheelbase_m=wb,
        mass_kg=mass,
        margin=margin,
        front_n_per_rad=C,
        rear_n_per_rad=C,
        n_front=layout.n_front,
        n_rear=layout.n_rear,
    )
    if margin >= 0:
        assert speed is None
    else:
        expected = (
            wb
            * (
                layout.n_front
                * C
                * layout.n_rear
                * C
                / (mass * (layout.n_front * l1 * C - layout.n_rear * l2 * C))
            )
            ** 0.5
        )
        assert speed == pytest.approx(expected)


def test_the_delta_s_critical_speed_is_the_study_s_to_the_last_bit() -> None:
    margin = understeer_margin(wheelbase_m=2.0, lsf=0.7103, front_n_per_rad=C, rear_n_per_rad=C)
    assert margin == 2 * (2.0 - 2.0 * 0.7103) * C - 2.0 * 0.7103 * C
    speed = critical_speed_ms(
        wheelbase_m=2.0, mass_kg=647.0, margin=margin, front_n_per_rad=C, rear_n_per_rad=C
    )
    assert speed == 2.0 * (2 * C * C / (647.0 * -margin)) ** 0.5


@pytest.mark.parametrize(
    ("front_track", "rear_track", "lsf", "expected"),
    [
        (0.0, 1.15, 0.6964, 1.15 / 2 * 0.6964),  # delta: (T_r / 2) LSF
        (1.20, 0.0, 0.2333, 1.20 / 2 * (1 - 0.2333)),  # tadpole: (T_f / 2) (1 - LSF)
        (1.30, 1.30, 0.487, 1.30 / 2),  # quadricycle, equal tracks: T / 2
        (1.20, 1.40, 0.5, 0.65),  # unequal tracks: the axis halfway
    ],
)
def test_the_rollover_axis_per_layout(
    front_track: float, rear_track: float, lsf: float, expected: float
) -> None:
    h = 0.55
    got = rollover_threshold_about_axis(
        front_track_m=front_track, rear_track_m=rear_track, cg_height_m=h, lsf=lsf
    )
    assert got == pytest.approx(expected / h)


def test_the_tadpole_s_rollover_threshold_falls_as_load_moves_rearward_the_delta_s_rises() -> None:
    def tadpole(lsf: float) -> float:
        return rollover_threshold_about_axis(front_track_m=1.2, rear_track_m=0.0, cg_height_m=0.55, lsf=lsf)

    def delta(lsf: float) -> float:
        return rollover_threshold_about_axis(front_track_m=0.0, rear_track_m=1.15, cg_height_m=0.55, lsf=lsf)

    assert tadpole(0.30) < tadpole(0.25)
    assert delta(0.70) > delta(0.65)
