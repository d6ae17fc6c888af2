"""The tools beyond Python some tests need (Debian's Chromium, axe-core, poppler): a test that needs
a missing one is skipped with the reason and how to install it, so the README's test command passes
on a fresh clone; on CI (`CI` set), where `.ci/run` installs them all, a missing tool is a failure."""

from __future__ import annotations

import os
from typing import NoReturn

import pytest


def tool_missing(what: str, how: str) -> NoReturn:
    """Skip the test (fail it on CI): `what` is missing, `how` installs it."""
    reason = f"{what} is missing: {how}"
    if os.environ.get("CI"):
        pytest.fail(reason)
    pytest.skip(reason)
