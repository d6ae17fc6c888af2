"""Argon2 at a test's cost: the production parameters (64 MiB, 3 passes, 4 lanes) take 0.1 to 1 s a
hash on a CI machine, and the tests sign in, make accounts and guess passwords thousands of times.

`cheap_password_hashing` swaps in the cheapest parameters Argon2 allows, for the tests' own process
only (a served `trikecert` process hashes at the production cost, and a hash verifies with the
parameters written in it, so accounts made either way sign in either way). What the app itself uses
is kept here, untouched, for tests/unit/test_password_cost.py, which checks the production parameters.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import pytest
from argon2 import PasswordHasher

from app.accounts import login, service

PRODUCTION_HASHER: PasswordHasher = service._hasher
PRODUCTION_DUMMY_HASH: str = login.unknown_email_hash()
TEST_HASHER = PasswordHasher(time_cost=1, memory_cost=8, parallelism=1)


@contextmanager
def cheap_password_hashing() -> Iterator[None]:
    """Hash and verify at TEST_HASHER's cost, the unknown-email dummy hash included, while inside."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(service, "_hasher", TEST_HASHER)
        cheap_dummy = TEST_HASHER.hash("not a real password, only for timing")
        patch.setattr(login, "unknown_email_hash", lambda: cheap_dummy)
        yield
