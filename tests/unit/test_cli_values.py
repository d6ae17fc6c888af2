"""A key id or a QR payload that begins with '-' reaches the command as its value: argparse alone took
it for an unknown option ("--anchor: expected one argument"), one key id in 64 being such."""

from __future__ import annotations

import pytest

from app.cli import build_parser
from app.cli_values import dash_safe

KID = "-Wq3xZ0e1d8k7b6a5c4f3g2h1i0j9k8l7m6n5o4p3q"  # base64url, as a key's thumbprint may begin
BUNDLE = ["trust-bundle", "--out", "b.jws"]
WITHDRAW = "withdraw-signing-key"


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (
            ["trust-bundle", "--out", "b.jws", "--anchor", KID],
            ["trust-bundle", "--out=b.jws", f"--anchor={KID}"],
        ),
        (["verify", "--offline", KID], ["verify", "--offline", "--", KID]),
        (
            ["withdraw-signing-key", KID, "--reason", "lost"],
            ["withdraw-signing-key", "--reason=lost", "--", KID],
        ),
        (["verify", "--", "-X"], ["verify", "--", "-X"]),
        (["verify", "--anchor=-abc", "p"], ["verify", "--anchor=-abc", "p"]),
        (["issue-certificate", "7", "-h"], ["issue-certificate", "7", "-h"]),
    ],
)
def test_values_that_begin_with_a_dash_stay_values(argv: list[str], expected: list[str]) -> None:
    assert dash_safe(build_parser(), argv) == expected


def test_the_parser_reads_them_as_the_command_means() -> None:
    parser = build_parser()
    bundle = parser.parse_args(dash_safe(parser, ["trust-bundle", "--out", "b.jws", "--anchor", KID]))
    assert bundle.anchor == [KID]
    verify = parser.parse_args(dash_safe(parser, ["verify", "--offline", "--anchor", KID, KID]))
    assert (verify.anchor, verify.payload) == ([KID], KID)
    withdraw = parser.parse_args(dash_safe(parser, ["withdraw-signing-key", KID, "--reason", "lost"]))
    assert (withdraw.kid, withdraw.reason) == (KID, "lost")
