"""Dates are worded in the reader's language, in the same order; English exactly as before."""

from __future__ import annotations

from datetime import date

import pytest

from app.i18n.active import use_locale
from app.web.formatting import long_date


@pytest.mark.parametrize(
    ("locale", "expected"),
    [
        ("en", "1 December 2027"),
        ("ha", "1 Disamba 2027"),
        ("yo", "1 Oṣù Ọ̀pẹ̀ 2027"),
        ("ig", "1 Disemba 2027"),
        ("pcm", "1 Disẹ́mba 2027"),
    ],
)
def test_a_long_date_in_each_language(locale: str, expected: str) -> None:
    with use_locale(locale):
        assert long_date(date(2027, 12, 1)) == expected
