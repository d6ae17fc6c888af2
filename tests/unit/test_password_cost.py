"""The app hashes passwords at the production cost; the tests run at a cheaper one (tests/password_cost.py),
so this is where the production parameters are checked."""

from __future__ import annotations

from argon2 import Type
from password_cost import PRODUCTION_DUMMY_HASH, PRODUCTION_HASHER

PRODUCTION_PREFIX = "$argon2id$v=19$m=65536,t=3,p=4$"


def test_the_app_hashes_passwords_with_argon2id_at_64_mib_3_passes_and_4_lanes() -> None:
    hasher = PRODUCTION_HASHER
    assert (hasher.type, hasher.memory_cost, hasher.time_cost, hasher.parallelism) == (Type.ID, 65536, 3, 4)
    made = hasher.hash("a long passphrase for the check")
    assert made.startswith(PRODUCTION_PREFIX)
    assert hasher.verify(made, "a long passphrase for the check")
    # An unknown email is verified against a hash of the same cost, so it takes as long as a wrong
    # password (app/accounts/login.py).
    assert PRODUCTION_DUMMY_HASH.startswith(PRODUCTION_PREFIX)
