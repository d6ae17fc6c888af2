"""`trikecert-station`: queue weighings from files or an indicator, send them, report what happened."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from app.station_client.delivery import Backoff, RunReport, deliver
from app.station_client.files import SourceError, Weighing, read_file
from app.station_client.http import post_weighing
from app.station_client.indicator import stable_readings, weighing_from_readings
from app.station_client.outbox import Outbox
from app.station_client.serial_lines import read_lines

EXIT_OK, EXIT_REJECTED, EXIT_USAGE, EXIT_PENDING = 0, 1, 2, 3


def _outbox(args: argparse.Namespace) -> Outbox:
    return Outbox(Path(args.queue))


def _enqueue(args: argparse.Namespace, weighings: Sequence[Weighing]) -> None:
    outbox = _outbox(args)
    try:
        ids, already = outbox.enqueue(weighings)
    finally:
        outbox.close()
    again = f" ({already} already queued)" if already else ""
    print(f"queued {len(ids)} weighing(s){again}: {', '.join(f'#{i}' for i in ids) or 'none new'}")


def cmd_queue(args: argparse.Namespace) -> int:
    """Queue every weighing of the files given (a row already queued is not queued again)."""
    weighings = [w for path in args.files for w in read_file(Path(path))]
    _enqueue(args, weighings)
    return EXIT_OK


def cmd_weigh(args: argparse.Namespace) -> int:
    """Read one weighing from the indicator (each wheel in turn) and queue it."""
    lines = read_lines(Path(args.indicator), baud=args.baud, idle_timeout=args.idle_timeout)
    readings = stable_readings(lines, continuous=args.continuous)
    weighing = weighing_from_readings(args.registration, readings, repeat=args.repeat, overall=args.overall)
    print(f"read {weighing.body['readings']} from {args.indicator}")
    _enqueue(args, [weighing])
    return EXIT_OK


def _key(args: argparse.Namespace) -> str:
    if args.key_file:
        return Path(args.key_file).read_text(encoding="utf-8").strip()
    key = os.environ.get("TRIKECERT_STATION_KEY", "").strip()
    if not key:
        raise SourceError("give the station key in TRIKECERT_STATION_KEY or a file named by --key-file")
    return key


def _summary(report: RunReport) -> int:
    print(
        f"{len(report.delivered)} delivered, {len(report.rejected)} rejected, "
        f"{len(report.pending)} still queued"
    )
    if report.stopped:
        print(f"stopped: {report.stopped}", file=sys.stderr)
    if report.pending:
        return EXIT_USAGE if report.stopped and "station key" in report.stopped else EXIT_PENDING
    return EXIT_REJECTED if report.rejected else EXIT_OK


def cmd_send(args: argparse.Namespace) -> int:
    """Send every queued weighing until the service has answered each, retrying while it cannot."""
    if not args.url.startswith(("http://", "https://")):
        raise SourceError(f"--url: give the service's address as http://... or https://..., not {args.url!r}")
    key = _key(args)
    outbox = _outbox(args)
    try:
        report = deliver(
            outbox,
            send=lambda weighing: post_weighing(args.url, key, weighing, timeout=args.timeout),
            backoff=Backoff(base=args.backoff_base, cap=args.backoff_cap),
            give_up_after=args.give_up_after,
        )
    finally:
        outbox.close()
    return _summary(report)


def cmd_submit(args: argparse.Namespace) -> int:
    """Queue the files' weighings, then send everything queued."""
    cmd_queue(args)
    return cmd_send(args)


def cmd_report(args: argparse.Namespace) -> int:
    """List every queued weighing: delivered (with its inspection id), rejected (with why), pending."""
    outbox = _outbox(args)
    try:
        weighings = outbox.every()
    finally:
        outbox.close()
    for w in weighings:
        detail = {
            "delivered": f"inspection {w.inspection_id}",
            "rejected": f"{w.http_status}: {w.message}",
            "pending": f"{w.attempts} tries" + (f"; last: {w.message}" if w.message else ""),
        }[w.state]
        print(f"{w.state:<9} #{w.id:<5} {w.registration_number:<12} {detail}")
    counts = {
        state: sum(w.state == state for w in weighings) for state in ("delivered", "rejected", "pending")
    }
    print(", ".join(f"{n} {state}" for state, n in counts.items()))
    return EXIT_PENDING if counts["pending"] else EXIT_OK


def _send_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--key-file", help="file holding the station key (else TRIKECERT_STATION_KEY)")
    parser.add_argument("--timeout", type=float, default=15.0, help="seconds to wait for one answer")
    parser.add_argument("--backoff-base", type=float, default=0.5, help="first retry delay, seconds")
    parser.add_argument("--backoff-cap", type=float, default=60.0, help="longest retry delay, seconds")
    parser.add_argument(
        "--give-up-after",
        type=float,
        default=600.0,
        help="stop when the service has not answered for this many seconds (the rest stay queued)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The command line: queue, weigh, send, submit, report."""
    parser = argparse.ArgumentParser(
        prog="trikecert-station", description="Deliver weighbridge weighings to trikecert exactly once."
    )
    parser.add_argument(
        "--queue",
        default=os.environ.get("TRIKECERT_STATION_QUEUE", "trikecert-station.db"),
        help="the queue file (TRIKECERT_STATION_QUEUE; default ./trikecert-station.db)",
    )
    parser.add_argument(
        "--url",
        default=os.environ.get("TRIKECERT_STATION_URL", "http://127.0.0.1:8000"),
        help="the service's address (TRIKECERT_STATION_URL)",
    )
    commands = parser.add_subparsers(dest="command", required=True)

    queue = commands.add_parser("queue", help="queue the weighings of CSV or JSON files")
    queue.add_argument("files", nargs="+")
    queue.set_defaults(handler=cmd_queue)

    weigh = commands.add_parser("weigh", help="queue one weighing read from a weighing indicator")
    weigh.add_argument("--registration", required=True)
    weigh.add_argument(
        "--indicator", required=True, help="serial device (/dev/ttyUSB0), pty or file of lines"
    )
    weigh.add_argument("--repeat", type=int, default=1, help="stable readings per wheel")
    weigh.add_argument("--overall", action="store_true", help="then read the whole vehicle too")
    weigh.add_argument("--continuous", action="store_true", help="the indicator sends continuously")
    weigh.add_argument("--baud", type=int, default=9600)
    weigh.add_argument("--idle-timeout", type=float, default=60.0, help="give up after this long silent")
    weigh.set_defaults(handler=cmd_weigh)

    send = commands.add_parser("send", help="send every queued weighing")
    _send_options(send)
    send.set_defaults(handler=cmd_send)

    submit = commands.add_parser("submit", help="queue the files' weighings, then send")
    submit.add_argument("files", nargs="+")
    _send_options(submit)
    submit.set_defaults(handler=cmd_submit)

    commands.add_parser("report", help="what was delivered, rejected, or is still queued").set_defaults(
        handler=cmd_report
    )
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script."""
    args = build_parser().parse_args(argv)
    try:
        code: int = args.handler(args)
    except SourceError as error:
        print(f"trikecert-station: {error}", file=sys.stderr)
        return EXIT_USAGE
    return code
