"""Each axle layout's title on a page: the core's own words in English, translated in the others."""

from __future__ import annotations

import pytest

from app.i18n.active import use_locale
from app.stability import LAYOUTS
from app.web.formatting import layout_title


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_a_layout_title_is_the_cores_in_english_and_translated_otherwise(name: str) -> None:
    with use_locale("en"):
        assert layout_title(name) == LAYOUTS[name].title
    for language in ("ha", "yo", "ig"):
        with use_locale(language):
            assert layout_title(name) != LAYOUTS[name].title
            assert layout_title(name).startswith(name.capitalize() + " (")
