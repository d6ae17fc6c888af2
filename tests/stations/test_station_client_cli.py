"""What the `trikecert-station` command tells its user: every sub-command's --help shows the defaults,
and a weighing that was only queued says so and how to send it."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

from app.station_client.cli import build_parser, main

INDICATOR_LINES = "ST,GS,+  108.0kg\nUS,GS,+  60.0kg\nST,GS,+  115.0kg\nUS,GS,+  60.0kg\nST,GS,+  135.0kg\n"


def help_text(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    with pytest.raises(SystemExit) as exited:
        main([*argv, "--help"])
    assert exited.value.code == 0
    return " ".join(capsys.readouterr().out.split())  # as one line: argparse wraps at any width


def sub_commands() -> dict[str, argparse.ArgumentParser]:
    (commands,) = (a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return dict(commands.choices)


def test_every_sub_commands_help_shows_each_default(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("TRIKECERT_STATION_QUEUE", raising=False)
    monkeypatch.delenv("TRIKECERT_STATION_URL", raising=False)
    checked = 0
    commands = sub_commands()
    assert set(commands) == {"queue", "weigh", "send", "submit", "retry", "report"}
    for name, parser in commands.items():
        shown = help_text(capsys, name)
        assert (
            "--queue QUEUE the queue file (env TRIKECERT_STATION_QUEUE) (default: trikecert-station.db)"
            in shown
        )
        for action in parser._actions:
            if action.option_strings and action.default not in (
                None,
                False,
                argparse.SUPPRESS,
                "==SUPPRESS==",
            ):
                assert f"(default: {action.default})" in shown, f"{name} {action.option_strings[0]}"
                checked += 1
        if name in ("send", "submit", "retry"):
            assert "(env TRIKECERT_STATION_URL) (default: http://127.0.0.1:8000)" in shown
            for default in ("(default: 15.0)", "(default: 0.5)", "(default: 60.0)", "(default: 600.0)"):
                assert default in shown, name
    assert checked >= 15, "the sends' four options, weigh's three, each time"
    assert "(default: trikecert-station.db)" in help_text(capsys)


def test_weigh_says_that_it_only_queued_and_how_to_send(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = tmp_path / "indicator.txt"
    lines.write_text(INDICATOR_LINES)
    queue = tmp_path / "queue.db"
    code = main(["weigh", "--queue", str(queue), "--registration", "BDG 252 QH", "--indicator", str(lines)])
    out = capsys.readouterr().out
    assert code == 0
    assert "queued 1 weighing(s): #1" in out
    assert "nothing is sent yet; send with: trikecert-station send" in out

    assert main(["--queue", str(queue), "report"]) == 3, "still queued"
    assert "pending   #1     BDG 252 QH   0 tries" in capsys.readouterr().out


def test_queue_says_how_to_send_but_not_when_nothing_new_was_queued(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    csv = tmp_path / "today.csv"
    csv.write_text("registration_number,front_kg,left_rear_kg,right_rear_kg\nBDG 252 QH,108,115,135\n")
    queue = str(tmp_path / "queue.db")
    assert main(["--queue", queue, "queue", str(csv)]) == 0
    assert "send with: trikecert-station send" in capsys.readouterr().out
    assert main(["queue", str(csv), "--queue", queue]) == 0
    out = capsys.readouterr().out
    assert "queued 0 weighing(s) (1 already queued): none new" in out
    assert "send with" not in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["send", "--url", "http://127.0.0.1:notaport"],
            "--url: 'http://127.0.0.1:notaport' is not an address",
        ),
        (["send", "--url", "ftp://example.org"], "--url: give the service's address as http://"),
        (
            ["send", "--key-file", "/nonexistent/key"],
            "--key-file /nonexistent/key: cannot read the station key",
        ),
        (["queue", "/nonexistent/today.csv"], "/nonexistent/today.csv: no such file"),
    ],
)
def test_a_usage_error_is_one_line_and_exit_status_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    code = main(["--queue", str(tmp_path / "queue.db"), *argv])
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("trikecert-station: ")
    assert message in err
