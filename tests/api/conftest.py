"""The API tests: Hypothesis keeps each regex character class's strategy (tests/api/regex_classes.py)
before tests/api/test_schemathesis.py builds its tests while being collected."""

from __future__ import annotations

import pytest
from regex_classes import keep_character_classes


def pytest_collectstart(collector: pytest.Collector) -> None:
    """Before a module of tests/api is collected (after pytest has started)."""
    keep_character_classes()
