"""Type assessment (LATERAL-STABILITY.md section 7): the study's three vehicles, the t table, edge cases.

Every figure is checked twice: against the reference's printed digits and against a computation
written here separately in floats (moments by hand, `statistics.stdev`, the printed t values).
"""

from __future__ import annotations

import math
from dataclasses import replace
from decimal import Decimal
from fractions import Fraction

import pytest
from scipy.special import stdtrit  # scipy.stats.t's quantile, without importing all of scipy.stats (1 s)

from app.stability import AssessmentInput, Rules, Seat, StabilityError, WheelReadings
from app.stability.type_assessment import T_95, Member, TypeAssessment, assess_type, t_95

SEATS = (Seat("driver", Decimal("0.9303")), *(Seat("passenger", Decimal("1.6303")),) * 3)
# The reference's illustrative readings: front, left rear, right rear, overall (kg).
STUDY = {
    "BDG 252 QH": (106, 114, 136, 357),
    "AGL 7180": (110, 116, 133, 360),
    "AGL 532 QH": (108, 115, 136, 360),
}
# Section 7's table: min, mean, max, s, upper 95 % bound (5 decimals), confident verdict.
PRINTED_SPREAD = [
    (0, "0.69167", "0.69639", "0.70028", "0.00437", "0.70375", False),
    (1, "0.65391", "0.65776", "0.66082", "0.00352", "0.66369", True),
    (2, "0.67695", "0.68029", "0.68300", "0.00307", "0.68547", False),
    (3, "0.69422", "0.69717", "0.69960", "0.00273", "0.70177", False),
    (4, "0.70766", "0.71030", "0.71250", "0.00245", "0.71443", False),
]
# The study's Table 4 (section 3): total kg, rear kg to 0.01, LSF and variance to 0.0001, verdict.
STUDY_TABLE = [
    (0, "359", "250.00", "0.6964", "-0.0297", False),
    (1, "431", "283.49", "0.6578", "0.0089", True),
    (2, "503", "342.18", "0.6803", "-0.0136", False),
    (3, "575", "400.87", "0.6972", "-0.0305", False),
    (4, "647", "459.56", "0.7103", "-0.0436", False),
]
PRINTED_T = {1: "6.313752", 2: "2.919986", 3: "2.353363", 4: "2.131847", 9: "1.833113", 29: "1.699127"}


def member(label: str, front: float, left: float, right: float, overall: float, **changes: object) -> Member:
    data = AssessmentInput(
        readings=WheelReadings(
            front_kg=(Decimal(str(front)),),
            left_rear_kg=(Decimal(str(left)),),
            right_rear_kg=(Decimal(str(right)),),
            overall_kg=(Decimal(str(overall)),),
        ),
        wheelbase_m=Decimal("2.000"),
        seats=SEATS,
        occupant_mass_kg=Decimal("72"),
    )
    return Member(label, replace(data, **changes), Rules())  # type: ignore[arg-type]


def by_hand_lsf(left: float, right: float, overall: float, occupants: int) -> float:
    """Moments about the front contact point, in floats: each occupant adds 72 x / WB to the rear."""
    xs = [0.9303, 1.6303, 1.6303, 1.6303][:occupants]
    return (left + right + sum(72 * x / 2.0 for x in xs)) / (overall + 72 * occupants)


def mean_sd(values: list[float]) -> tuple[float, float]:
    """The mean and the sample standard deviation (n - 1), in floats."""
    mean = sum(values) / len(values)
    return mean, math.sqrt(sum((v - mean) ** 2 for v in values) / (len(values) - 1))


@pytest.fixture(scope="module")
def study() -> TypeAssessment:
    return assess_type([member(label, *readings) for label, readings in STUDY.items()])


def five(value: Fraction | Decimal) -> str:
    """A figure to the reference's 5 printed decimals."""
    if isinstance(value, Fraction):
        value = Decimal(value.numerator) / Decimal(value.denominator)
    return f"{value:.5f}"


@pytest.mark.parametrize(("occupants", "low", "mean", "high", "sd", "upper", "confident"), PRINTED_SPREAD)
def test_the_study_vehicles_spread_matches_section_7_to_the_printed_digits(
    study: TypeAssessment,
    occupants: int,
    low: str,
    mean: str,
    high: str,
    sd: str,
    upper: str,
    confident: bool,
) -> None:
    case = study.spread[occupants]
    assert case.occupants == occupants
    assert [five(case.min_lsf), five(case.mean_lsf), five(case.max_lsf)] == [low, mean, high]
    assert [five(case.sd_lsf), five(case.upper_95_lsf)] == [sd, upper]
    assert case.confident_compliant is confident


@pytest.mark.parametrize("occupants", range(5))
def test_the_spread_agrees_with_a_float_computation_by_hand(study: TypeAssessment, occupants: int) -> None:
    lsfs = [by_hand_lsf(left, right, overall, occupants) for _f, left, right, overall in STUDY.values()]
    mean, sd = mean_sd(lsfs)
    upper = mean + float(PRINTED_T[2]) * sd / math.sqrt(3)
    case = study.spread[occupants]
    assert float(case.min_lsf) == pytest.approx(min(lsfs), abs=1e-12)
    assert float(case.max_lsf) == pytest.approx(max(lsfs), abs=1e-12)
    assert float(case.mean_lsf) == pytest.approx(mean, abs=1e-12)
    assert float(case.sd_lsf) == pytest.approx(sd, abs=1e-12)
    assert float(case.upper_95_lsf) == pytest.approx(upper, abs=1e-6)
    assert case.confident_compliant is (upper < 2 / 3)


@pytest.mark.parametrize(("occupants", "total", "rear", "lsf", "variance", "compliant"), STUDY_TABLE)
def test_the_types_table_4_from_the_mean_readings_is_the_studys(
    study: TypeAssessment, occupants: int, total: str, rear: str, lsf: str, variance: str, compliant: bool
) -> None:
    case = study.table.cases[occupants]
    assert float(case.total_kg) == float(total)
    assert f"{float(case.rear_kg):.2f}" == rear
    assert f"{float(case.lsf):.4f}" == lsf
    assert f"{float(case.variance):.4f}" == variance
    assert case.compliant is compliant
    assert case.lsf == Fraction(by_hand_lsf(115, 135, 359, occupants)).limit_denominator(10**9)


def test_the_study_type_is_certified_for_the_driver_alone(study: TypeAssessment) -> None:
    assert study.compliant is False
    assert study.max_compliant_occupants == 1
    assert [v.cases[1].lsf < Fraction(2, 3) for v in study.vehicles] == [True, True, True]


@pytest.mark.parametrize(("df", "printed"), PRINTED_T.items())
def test_the_t_table_gives_the_reference_values_to_six_decimals(df: int, printed: str) -> None:
    assert f"{t_95(df):.6f}" == printed


@pytest.mark.parametrize("n", range(2, 61))
def test_the_t_table_is_scipys_rounded_up_for_2_to_60_vehicles(n: int) -> None:
    exact = float(stdtrit(n - 1, 0.95))
    assert 0 <= float(t_95(n - 1)) - exact < 1.1e-9


@pytest.mark.parametrize("df", [60, 61, 79, 80, 99, 150, 999, 1000, 5000])
def test_beyond_the_table_t_is_never_smaller_than_the_true_value(df: int) -> None:
    assert float(t_95(df)) >= float(stdtrit(df, 0.95))
    assert t_95(df) in T_95.values()


def test_two_vehicles_use_t_with_one_degree_of_freedom() -> None:
    pair = assess_type([member("A 1", 108, 115, 135, 359), member("A 2", 110, 116, 133, 360)])
    lsfs = [by_hand_lsf(115, 135, 359, 1), by_hand_lsf(116, 133, 360, 1)]
    mean, sd = mean_sd(lsfs)
    upper = mean + 6.313752 * sd / math.sqrt(2)
    driver = pair.spread[1]
    assert driver.t == t_95(1)
    assert float(driver.upper_95_lsf) == pytest.approx(upper, abs=1e-6)
    # Both vehicles comply with the driver alone, but two of them do not show it with confidence.
    assert all(v.cases[1].compliant for v in pair.vehicles)
    assert driver.confident_compliant is (upper < 2 / 3) is False
    assert pair.max_compliant_occupants == 0


def test_identical_vehicles_have_no_spread_and_the_bound_is_the_mean() -> None:
    same = assess_type([member(f"S {i}", 108, 115, 135, 359) for i in range(3)])
    for case, row in zip(same.spread, same.table.cases, strict=True):
        assert case.sample_variance == 0
        assert case.sd_lsf == 0
        assert case.min_lsf == case.mean_lsf == case.max_lsf == row.lsf
        assert case.upper_95_lsf == Decimal(row.lsf.numerator) / Decimal(row.lsf.denominator)
        assert case.confident_compliant is row.compliant
    assert same.max_compliant_occupants == 1


def test_a_bound_of_exactly_two_thirds_is_not_compliant() -> None:
    # a = 103.2, b = 91.3, c = 115.1 gives LSF exactly 2/3 (section 2); twice, so s = 0.
    pair = assess_type([member(f"E {i}", 103.2, 91.3, 115.1, 309.6) for i in range(2)])
    assert pair.spread[0].mean_lsf == Fraction(2, 3)
    assert pair.spread[0].confident_compliant is False


def test_one_vehicle_is_refused() -> None:
    with pytest.raises(StabilityError) as refused:
        assess_type([member("BDG 252 QH", 108, 115, 135, 359)])
    assert (refused.value.field, refused.value.rule) == ("inspection_ids", "too_few")


@pytest.mark.parametrize(
    ("changes", "what"),
    [
        ({"seats": SEATS[:3]}, "seat layout"),
        ({"occupant_mass_kg": Decimal("75")}, "occupant mass"),
        ({"wheelbase_m": Decimal("2.1")}, "wheelbase"),
    ],
)
def test_different_layouts_or_masses_are_refused_naming_the_vehicles(
    changes: dict[str, object], what: str
) -> None:
    members = [member("BDG 252 QH", 106, 114, 136, 357), member("AGL 7180", 110, 116, 133, 360, **changes)]
    with pytest.raises(StabilityError) as refused:
        assess_type(members)
    assert refused.value.field == "inspection_ids"
    assert "BDG 252 QH" in refused.value.message
    assert "AGL 7180" in refused.value.message
    assert what in refused.value.message
