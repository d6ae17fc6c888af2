"""Where the station client reads weighings: CSV and JSON files, and a weighing indicator's serial
output (a file of lines, or a live pty as a serial port would be), keeping only stable readings."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from decimal import Decimal
from pathlib import Path

import pytest

from app.station_client.files import SourceError, read_file
from app.station_client.indicator import parse_line, stable_readings, weighing_from_readings
from app.station_client.outbox import Outbox
from app.station_client.serial_lines import read_lines

INDICATOR_OUTPUT = """\
US,GS,+  104.5kg
US,GS,+  107.5kg
ST,GS,+  108.0kg
ST,GS,+    0.0kg
US,GS,+  113.0kg
ST,GS,+  115.0kg
OL,GS,+  ----- kg
garbage line
ST,GS,+  135.0kg
ST,GS,+  359.0kg
"""


def test_a_csv_row_is_one_weighing_and_a_cell_may_hold_repeated_readings(tmp_path: Path) -> None:
    path = tmp_path / "weighings.csv"
    path.write_text(
        "registration_number,front_kg,left_rear_kg,right_rear_kg,overall_kg\n"
        "BDG 252 QH,107;108;109,115,135,359\n"
        "\n"
        "KTU 417 XA,200,80.5,80,\n"
    )
    first, second = read_file(path)
    assert first.body == {
        "registration_number": "BDG 252 QH",
        "readings": {
            "front_kg": [107, 108, 109],
            "left_rear_kg": 115,
            "right_rear_kg": 135,
            "overall_kg": 359,
        },
    }
    assert second.body["readings"] == {"front_kg": 200, "left_rear_kg": 80.5, "right_rear_kg": 80}
    assert first.source is not None
    assert first.source != second.source


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("registration_number,front_kg,left_rear_kg\nX,1,2\n", "missing: right_rear_kg"),
        ("registration_number,frnt_kg,left_rear_kg,right_rear_kg,front_kg\n", "unknown: frnt_kg"),
        ("registration_number,front_kg,left_rear_kg,right_rear_kg\nX,1o8,1,1\n", "weighings.csv:2 front_kg"),
    ],
)
def test_a_bad_csv_is_refused_saying_where(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "weighings.csv"
    path.write_text(text)
    with pytest.raises(SourceError, match=message):
        read_file(path)


def test_a_json_file_holds_the_apis_own_bodies(tmp_path: Path) -> None:
    body = {
        "registration_number": "BDG 252 QH",
        "readings": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 135},
    }
    path = tmp_path / "weighings.json"
    path.write_text(json.dumps({"weighings": [body, {**body, "wheelbase_m": 2.0}]}))
    weighings = read_file(path)
    assert [w.body for w in weighings] == [body, {**body, "wheelbase_m": 2.0}]
    path.write_text(json.dumps([{"readings": {}}]))
    with pytest.raises(SourceError, match="needs registration_number"):
        read_file(path)


def test_queueing_the_same_file_twice_queues_each_weighing_once(tmp_path: Path) -> None:
    path = tmp_path / "weighings.csv"
    path.write_text("registration_number,front_kg,left_rear_kg,right_rear_kg\nA1,1,2,3\nB2,4,5,6\n")
    outbox = Outbox(tmp_path / "queue.db")
    assert outbox.enqueue(read_file(path)) == ([1, 2], 0)
    path.write_text(path.read_text() + "C3,7,8,9\n")  # the day's file grows
    assert outbox.enqueue(read_file(path)) == ([3], 2)
    keys = {w.idempotency_key for w in outbox.every()}
    assert len(keys) == 3
    outbox.close()
    assert len(Outbox(tmp_path / "queue.db").pending()) == 3, "the queue outlives the process"


def test_only_stable_positive_weights_are_readings() -> None:
    assert parse_line("ST,GS,+  108.0kg") is not None
    assert parse_line("US,GS,+  107.5kg") == parse_line("US,GS,+107.5 kg")
    assert parse_line("OL,GS,+  ----- kg") is None
    assert parse_line("ST,NT,-   1.5kg").kg == Decimal("-1.5")  # type: ignore[union-attr]
    assert parse_line("ST,GS,+   0.36t").kg == Decimal("360.00")  # type: ignore[union-attr]
    assert list(stable_readings(INDICATOR_OUTPUT.splitlines())) == [
        Decimal("108.0"), Decimal("115.0"), Decimal("135.0"), Decimal("359.0")
    ]  # fmt: skip


def test_in_continuous_mode_one_settling_is_one_reading() -> None:
    lines = ["ST,GS,+108.0kg"] * 5 + ["US,GS,+60.0kg", "ST,GS,+108.5kg", "ST,GS,+108.5kg", "ST,GS,+0.0kg"]
    lines += ["ST,GS,+108.5kg", "ST,GS,+109.0kg"]
    assert list(stable_readings(lines, continuous=True)) == [
        Decimal("108.0"), Decimal("108.5"), Decimal("108.5"), Decimal("109.0")
    ]  # fmt: skip
    assert len(list(stable_readings(lines))) == 9


def test_a_weighing_takes_each_wheel_in_turn() -> None:
    readings = stable_readings(INDICATOR_OUTPUT.splitlines())
    weighing = weighing_from_readings("BDG 252 QH", readings, overall=True)
    assert weighing.body["readings"] == {
        "front_kg": 108,
        "left_rear_kg": 115,
        "right_rear_kg": 135,
        "overall_kg": 359,
    }
    with pytest.raises(SourceError, match="right_rear_kg needs 2, got 0"):
        weighing_from_readings("X1", iter([Decimal(1), Decimal(2), Decimal(3), Decimal(4)]), repeat=2)


def test_a_file_of_indicator_lines_is_a_line_source(tmp_path: Path) -> None:
    path = tmp_path / "capture.txt"
    path.write_text(INDICATOR_OUTPUT.replace("\n", "\r\n"))
    assert list(read_lines(path))[2] == "ST,GS,+  108.0kg"


def test_weigh_reads_a_live_serial_line_and_queues_the_weighing(tmp_path: Path) -> None:
    """The client reads a pty as it would /dev/ttyUSB0, while the 'indicator' is still sending."""
    master, slave = os.openpty()
    queue = tmp_path / "queue.db"
    client = subprocess.Popen(
        [sys.executable, "-m", "app.station_client", "--queue", str(queue), "weigh", "--registration",
         "BDG 252 QH", "--indicator", os.ttyname(slave), "--repeat", "2", "--idle-timeout", "5"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert client.stdout is not None
        # The client opens the port first, as at a real station (what came before it is discarded).
        assert client.stdout.readline().startswith(f"reading {os.ttyname(slave)}: weigh the front wheel")
        for line in ["US,GS,+ 90.0kg", "ST,GS,+108.0kg", "ST,GS,+108.5kg", "US,GS,+114.0kg", "ST,GS,+115.0kg",
                     "ST,GS,+115.5kg", "ST,GS,+135.0kg", "ST,GS,+134.5kg"]:  # fmt: skip
            os.write(master, f"{line}\r\n".encode())
            time.sleep(0.02)
        out, err = client.communicate(timeout=15)
    finally:
        os.close(master)
        os.close(slave)
    assert client.returncode == 0, err
    (queued,) = Outbox(queue).pending()
    assert json.loads(queued.body) == {
        "registration_number": "BDG 252 QH",
        "readings": {"front_kg": [108, 108.5], "left_rear_kg": [115, 115.5], "right_rear_kg": [135, 134.5]},
    }
    assert "queued 1 weighing" in out
    assert "nothing is sent yet; send with: trikecert-station send" in out


def test_the_indicator_reads_each_layout_s_wheels_in_the_order_round_the_vehicle() -> None:
    from decimal import Decimal

    from app.station_client.indicator import weighing_from_readings

    readings = iter(Decimal(v) for v in ("186", "182", "112", "480"))
    tadpole = weighing_from_readings("TDP 101 EV", readings, overall=True, layout="tadpole")
    assert list(tadpole.body["readings"].items()) == [
        ("left_front_kg", 186),
        ("right_front_kg", 182),
        ("rear_kg", 112),
        ("overall_kg", 480),
    ]
    readings = iter(Decimal(v) for v in ("150", "148", "140", "143"))
    quadricycle = weighing_from_readings("QDC 202 AA", readings, layout="quadricycle")
    assert list(quadricycle.body["readings"]) == [
        "left_front_kg",
        "right_front_kg",
        "left_rear_kg",
        "right_rear_kg",
    ]


def test_a_csv_of_tadpoles_is_read_and_a_half_layout_names_what_is_missing(tmp_path: Path) -> None:
    path = tmp_path / "weighings.csv"
    path.write_text(
        "registration_number,left_front_kg,right_front_kg,rear_kg,overall_kg\nTDP 101 EV,186,182,112,480\n"
    )
    [weighing] = read_file(path)
    assert weighing.body["readings"] == {
        "left_front_kg": 186,
        "right_front_kg": 182,
        "rear_kg": 112,
        "overall_kg": 480,
    }
    path.write_text("registration_number,left_front_kg,right_front_kg\nTDP 101 EV,186,182\n")
    with pytest.raises(SourceError, match="missing: rear_kg"):
        read_file(path)
