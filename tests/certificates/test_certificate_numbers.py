"""Certificate numbers: format, and a check letter that catches every single mistyped character and
every swap of neighbouring characters (proved exhaustively for a sample of numbers)."""

from __future__ import annotations

import random
import string

import pytest

from app.trust.numbers import (
    CHECK_ALPHABET,
    MODULUS,
    CertificateNumber,
    InvalidNumber,
    check_letter,
    is_valid_number,
    normalise,
    parse_number,
)

TYPED = string.digits + string.ascii_uppercase + "-"
_rng = random.Random(20261123)
SAMPLE = [
    CertificateNumber(2026, 1),
    CertificateNumber(2026, 123),
    CertificateNumber(2026, 999_999),
    CertificateNumber(2030, 505_050),
    CertificateNumber(1999, 900_009),
    *[CertificateNumber(_rng.randint(2000, 2099), _rng.randint(1, 999_999)) for _ in range(60)],
]


@pytest.mark.parametrize(
    ("year", "sequence", "printed"),
    [
        (2026, 1, f"TRK-2026-000001-{check_letter('2026000001')}"),
        (2026, 123, f"TRK-2026-000123-{check_letter('2026000123')}"),
        (2031, 999_999, f"TRK-2031-999999-{check_letter('2031999999')}"),
    ],
)
def test_a_number_prints_as_prefix_year_six_digit_sequence_and_check_letter(
    year: int, sequence: int, printed: str
) -> None:
    assert str(CertificateNumber(year, sequence)) == printed
    assert parse_number(printed) == CertificateNumber(year, sequence)


@pytest.mark.parametrize(
    "written", ["trk-2026-000123-{c}", " TRK 2026 000123 {c} ", "TRK2026000123{c}", "trk--2026-000123-{c}"]
)
def test_case_spaces_and_hyphens_are_forgiven(written: str) -> None:
    letter = check_letter("2026000123").lower()
    assert parse_number(written.format(c=letter)) == CertificateNumber(2026, 123)


@pytest.mark.parametrize(
    "text",
    ["", "TRK-2026-123-A", "TRK-2026-0000123-A", "ABC-2026-000123-A", "TRK-2026-000123", "TRK-२०२6-000123-A"],
)
def test_malformed_numbers_are_refused(text: str) -> None:
    with pytest.raises(InvalidNumber):
        parse_number(text)


def test_the_check_alphabet_has_23_letters_without_i_o_or_q() -> None:
    assert len(CHECK_ALPHABET) == MODULUS == 23
    assert not set("IOQ") & set(CHECK_ALPHABET)
    assert CHECK_ALPHABET.isalpha()
    assert CHECK_ALPHABET.isupper()


def test_why_it_works_every_weighted_difference_is_nonzero_modulo_23() -> None:
    """Weights 1..10, digits differing by 1..9: neither a weight nor a difference is a multiple of 23."""
    for position in range(1, 11):
        for difference in range(1, 10):
            assert position * difference % MODULUS != 0  # one digit mistyped
            for other in range(position + 1, 11):
                assert (other - position) * difference % MODULUS != 0  # two digits swapped


@pytest.mark.parametrize("number", SAMPLE, ids=str)
def test_every_single_mistyped_character_is_refused(number: CertificateNumber) -> None:
    printed = str(number)
    for index, original in enumerate(printed):
        for typed in TYPED:
            if typed != original:
                mistyped = printed[:index] + typed + printed[index + 1 :]
                assert not is_valid_number(mistyped), mistyped


@pytest.mark.parametrize("number", SAMPLE, ids=str)
def test_every_swap_of_neighbours_is_refused_or_only_moves_a_hyphen(number: CertificateNumber) -> None:
    printed = str(number)
    for form in (printed, normalise(printed)):
        for index in range(len(form) - 1):
            left, right = form[index], form[index + 1]
            if left == right:
                continue
            swapped = form[:index] + right + left + form[index + 2 :]
            if "-" in (left, right):
                assert not is_valid_number(swapped) or parse_number(swapped) == number
            else:
                assert not is_valid_number(swapped), swapped


def test_sequences_outside_one_to_999999_do_not_exist() -> None:
    with pytest.raises(InvalidNumber):
        CertificateNumber(2026, 0)
    with pytest.raises(InvalidNumber):
        CertificateNumber(2026, 1_000_000)
