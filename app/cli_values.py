"""Command-line values that begin with '-': a key id (base64url) or a QR payload (base45) may, and
argparse would read such a value as an unknown option ("--anchor: expected one argument")."""

from __future__ import annotations

import argparse
from collections.abc import Sequence


def _options_of(parser: argparse.ArgumentParser) -> tuple[set[str], set[str]]:
    """Every option string of the parser and its sub-commands, and those that take one value."""
    options: set[str] = set()
    valued: set[str] = set()
    for action in parser._actions:  # argparse keeps no public list of a parser's actions
        options.update(action.option_strings)
        takes_one = (
            isinstance(action, argparse._StoreAction | argparse._AppendAction) and action.nargs is None
        )
        if takes_one:
            valued.update(action.option_strings)
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                sub_options, sub_valued = _options_of(sub)
                options |= sub_options
                valued |= sub_valued
    return options, valued


def dash_safe(parser: argparse.ArgumentParser, argv: Sequence[str]) -> list[str]:
    """The arguments as argparse must read them: `--option VALUE` as `--option=VALUE`, and any other
    token that begins with '-' and names no option moved after `--`, where it is positional."""
    options, valued = _options_of(parser)
    kept: list[str] = []
    positional: list[str] = []
    args = list(argv)
    index = 0
    while index < len(args):
        arg = args[index]
        if arg == "--":
            positional.extend(args[index + 1 :])
            break
        if arg in valued and index + 1 < len(args):
            kept.append(f"{arg}={args[index + 1]}")
            index += 2
            continue
        if arg.startswith("-") and len(arg) > 1 and arg.split("=", 1)[0] not in options:
            positional.append(arg)
        else:
            kept.append(arg)
        index += 1
    return [*kept, "--", *positional] if positional else kept
