"""Certificate numbers like TRK-2026-000123-K: year, sequence and a check letter (pure, no I/O).

The check letter is a weighted sum modulo the prime 23, in the manner of the Irish PPS number:
the ten digits (year and sequence) are weighted 1, 2, ..., 10 from the left and the letter is
the one whose value brings the sum to 0 (mod 23). Because 23 is prime, every weight is below 23
and every two digits differ by less than 23, the letter changes when any one digit is mistyped
and when any two digits (adjacent or not) are swapped. Mistyping a letter, a hyphen or the check
letter itself, or swapping the check letter with a digit, breaks the fixed format instead.
The alphabet leaves out I, O and Q, which are easily read as 1, 0 and 0.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal

PREFIX = "TRK"
SEQUENCE_DIGITS = 6
MAX_SEQUENCE = 10**SEQUENCE_DIGITS - 1
MODULUS = 23
CHECK_ALPHABET = "ABCDEFGHJKLMNPRSTUVWXYZ"
assert len(CHECK_ALPHABET) == MODULUS

_COMPACT = re.compile(rf"^{PREFIX}([0-9]{{4}})([0-9]{{{SEQUENCE_DIGITS}}})([A-Z])$")


class InvalidNumber(ValueError):
    """The text is not a well-formed certificate number (`rule` format) or its check letter is wrong."""

    def __init__(self, message: str, rule: Literal["format", "check_letter"] = "format") -> None:
        super().__init__(message)
        self.rule = rule


def check_letter(digits: str) -> str:
    """The check letter of the year and sequence digits, e.g. '2026000123' -> one letter."""
    if not digits.isdigit() or not digits.isascii():
        raise ValueError(f"check_letter: digits only, got {digits!r}")
    total = sum(weight * int(digit) for weight, digit in enumerate(digits, start=1))
    return CHECK_ALPHABET[-total % MODULUS]


@dataclass(frozen=True, order=True)
class CertificateNumber:
    """A certificate number: the year it was issued in and its sequence within that year."""

    year: int
    sequence: int

    def __post_init__(self) -> None:
        if not 1000 <= self.year <= 9999:
            raise InvalidNumber(f"the year {self.year} does not have four digits")
        if not 1 <= self.sequence <= MAX_SEQUENCE:
            raise InvalidNumber(f"the sequence {self.sequence} is outside 1 to {MAX_SEQUENCE}")

    @property
    def digits(self) -> str:
        """The year and sequence as the ten digits the check letter covers."""
        return f"{self.year:04d}{self.sequence:0{SEQUENCE_DIGITS}d}"

    def __str__(self) -> str:
        digits = self.digits
        return f"{PREFIX}-{digits[:4]}-{digits[4:]}-{check_letter(digits)}"


def normalise(text: str) -> str:
    """Upper case without spaces or hyphens: ' trk-2026-000123-k ' -> 'TRK2026000123K'."""
    return re.sub(r"[\s\-]+", "", text).upper()


def parse_number(text: str) -> CertificateNumber:
    """The number written in `text` (case, spaces and hyphens are forgiven), or InvalidNumber."""
    match = _COMPACT.match(normalise(text))
    if match is None:
        raise InvalidNumber(
            f"{text.strip()[:40]!r} is not a certificate number; they look like TRK-2026-000123-K"
        )
    year, sequence, letter = match.groups()
    if check_letter(year + sequence) != letter:
        raise InvalidNumber(
            f"{text.strip()[:40]!r} has a wrong check letter: a character is mistyped or two are swapped",
            rule="check_letter",
        )
    return CertificateNumber(int(year), int(sequence))


def is_valid_number(text: str) -> bool:
    """True when `text` is a well-formed number whose check letter agrees."""
    try:
        parse_number(text)
    except InvalidNumber:
        return False
    return True
