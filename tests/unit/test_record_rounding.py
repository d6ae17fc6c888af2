"""Storage rounding of exact values: half-even, once, on the exact fraction (app/inspections/record.py).

Two references are computed here apart from the code under test: Decimal's own half-even rounding of
the quotient taken to 200 digits (enough to be exact on a tie, and far from one otherwise, for these
denominators), and Python's exact `round` of the Fraction.
"""

from __future__ import annotations

import random
from decimal import ROUND_HALF_EVEN, Decimal, localcontext
from fractions import Fraction

import pytest

from app.inspections.record import quantize


def by_decimal(value: Fraction, places: int) -> Decimal:
    """Decimal's half-even rounding of the quotient worked out to 200 digits."""
    with localcontext() as context:
        context.prec = 200
        quotient = Decimal(value.numerator) / Decimal(value.denominator)
        return quotient.quantize(Decimal(1).scaleb(-places), ROUND_HALF_EVEN)


def by_round(value: Fraction, places: int) -> Decimal:
    """Python's exact half-even `round` of the Fraction, written out as a decimal."""
    return Decimal(round(value * 10**places)).scaleb(-places)


@pytest.mark.parametrize(
    ("value", "places", "expected"),
    [
        pytest.param(Fraction(1, 2), 0, "0", id="half-to-even-down"),
        pytest.param(Fraction(3, 2), 0, "2", id="half-to-even-up"),
        pytest.param(Fraction(-1, 2), 0, "0", id="minus-half-to-even"),
        pytest.param(Fraction(-3, 2), 0, "-2", id="minus-three-halves"),
        pytest.param(Fraction(125, 1000), 2, "0.12", id="tie-at-the-last-place"),
        pytest.param(Fraction(135, 1000), 2, "0.14", id="tie-rounds-to-the-even-digit"),
        pytest.param(Fraction(250, 359), 8, "0.69637883", id="the-study-empty-case-lsf"),
        pytest.param(Fraction(2, 3) - Fraction(250, 359), 8, "-0.02971216", id="its-variance"),
        pytest.param(Fraction(0), 6, "0.000000", id="zero-keeps-its-places"),
        pytest.param(Fraction(1234567, 8), 4, "154320.8750", id="exact-in-fewer-places"),
    ],
)
def test_a_fraction_is_stored_rounded_half_even_once(value: Fraction, places: int, expected: str) -> None:
    assert quantize(value, places) == Decimal(expected)
    assert str(quantize(value, places)) == str(Decimal(expected))


def test_a_value_just_past_a_tie_rounds_away_even_where_28_digits_would_see_the_tie() -> None:
    # 0.123456785 + 1e-30: a 28-digit division first rounds it onto the tie, which half-even then
    # takes down to ...78; rounded once on the exact value it is past the tie, so ...79.
    value = Fraction(123456785, 10**9) + Fraction(1, 10**30)
    assert quantize(value, 8) == Decimal("0.12345679")


def test_random_fractions_agree_with_both_references() -> None:
    generator = random.Random(20261202)
    for _ in range(20_000):
        value = Fraction(generator.randint(-(10**12), 10**12), generator.randint(1, 10**9))
        places = generator.randint(0, 10)
        stored = quantize(value, places)
        assert stored == by_decimal(value, places) == by_round(value, places), (value, places)
