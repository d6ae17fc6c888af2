"""`trikecert-station`: queue weighings from files or an indicator, send them, report what happened."""

from __future__ import annotations

import argparse
import os
import sqlite3
import sys
from collections.abc import Sequence
from pathlib import Path
from urllib.parse import urlsplit

from app.station_client.delivery import Backoff, RunReport, deliver, retry_hint
from app.station_client.files import SourceError, Weighing, read_file
from app.station_client.http import post_weighing
from app.station_client.indicator import stable_readings, weighing_from_readings
from app.station_client.outbox import Outbox
from app.station_client.serial_lines import read_lines

EXIT_OK, EXIT_REJECTED, EXIT_USAGE, EXIT_PENDING = 0, 1, 2, 3


def _outbox(args: argparse.Namespace) -> Outbox:
    return Outbox(Path(args.queue))


SEND_HINT = "nothing is sent yet; send with: trikecert-station send"


def _enqueue(args: argparse.Namespace, weighings: Sequence[Weighing], *, hint: bool) -> None:
    outbox = _outbox(args)
    try:
        ids, already = outbox.enqueue(weighings)
    finally:
        outbox.close()
    again = f" ({already} already queued)" if already else ""
    print(f"queued {len(ids)} weighing(s){again}: {', '.join(f'#{i}' for i in ids) or 'none new'}")
    if hint and ids:
        print(SEND_HINT)


def cmd_queue(args: argparse.Namespace) -> int:
    """Queue every weighing of the files given (a row already queued is not queued again)."""
    weighings = [w for path in args.files for w in read_file(Path(path))]
    _enqueue(args, weighings, hint=args.command == "queue")
    return EXIT_OK


WHEEL_ORDER_WORDS = {
    "delta": "the front wheel, the left rear, the right rear",
    "tadpole": "the left front wheel, the right front, the rear",
    "quadricycle": "the left front wheel, the right front, the left rear, the right rear",
}


def cmd_weigh(args: argparse.Namespace) -> int:
    """Read one weighing from the indicator (each wheel in turn) and queue it."""
    wheels = WHEEL_ORDER_WORDS[args.layout] + (", then the whole vehicle" if args.overall else "")
    lines = read_lines(
        Path(args.indicator),
        baud=args.baud,
        idle_timeout=args.idle_timeout,
        ready=lambda: print(
            f"reading {args.indicator}: weigh {wheels} ({args.repeat} stable reading(s) each)", flush=True
        ),
    )
    readings = stable_readings(lines, continuous=args.continuous)
    weighing = weighing_from_readings(
        args.registration, readings, repeat=args.repeat, overall=args.overall, layout=args.layout
    )
    print(f"read {weighing.body['readings']} from {args.indicator}")
    _enqueue(args, [weighing], hint=True)
    return EXIT_OK


def _key(args: argparse.Namespace) -> str:
    if args.key_file:
        try:
            return Path(args.key_file).read_text(encoding="utf-8").strip()
        except (OSError, UnicodeDecodeError) as error:
            raise SourceError(f"--key-file {args.key_file}: cannot read the station key ({error})") from error
    key = os.environ.get("TRIKECERT_STATION_KEY", "").strip()
    if not key:
        raise SourceError("give the station key in TRIKECERT_STATION_KEY or a file named by --key-file")
    return key


def _summary(report: RunReport) -> int:
    print(
        f"{len(report.delivered)} delivered, {len(report.rejected)} rejected, "
        f"{len(report.pending)} still queued"
    )
    if report.failed_tries:
        causes = ", ".join(f"{n} {cause}" for cause, n in sorted(report.failed_tries.items()))
        print(
            f"{report.failed_tries.total()} tries without a final answer (retried or left queued): {causes}"
        )
    if report.rejected:
        print("once a rejection's cause is fixed, send it again with: trikecert-station retry ID")
    if report.stopped:
        print(f"stopped: {report.stopped}", file=sys.stderr)
    if report.pending:
        return EXIT_USAGE if report.stopped and "station key" in report.stopped else EXIT_PENDING
    return EXIT_REJECTED if report.rejected else EXIT_OK


def _check_url(url: str) -> None:
    try:
        parts = urlsplit(url)
        _port = parts.port  # a port that is not a number raises here rather than on every try
    except ValueError as error:
        raise SourceError(f"--url: {url!r} is not an address ({error})") from error
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise SourceError(f"--url: give the service's address as http://... or https://..., not {url!r}")


def cmd_send(args: argparse.Namespace) -> int:
    """Send every queued weighing until the service has answered each, retrying while it cannot."""
    _check_url(args.url)
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


def cmd_retry(args: argparse.Namespace) -> int:
    """Put rejected weighings back in the queue (their cause fixed), then send everything queued."""
    _check_url(args.url)
    _key(args)  # before anything changes: a missing key would leave them queued but unsent
    outbox = _outbox(args)
    try:
        found = [(weighing_id, outbox.find(weighing_id)) for weighing_id in dict.fromkeys(args.ids)]
        missing = [f"#{weighing_id}" for weighing_id, weighing in found if weighing is None]
        if missing:
            raise SourceError(
                f"no weighing {', '.join(missing)} in the queue (see: trikecert-station report)"
            )
        for weighing in (w for _, w in found if w is not None):
            if outbox.requeue(weighing.id):
                why = f"{weighing.http_status}: {weighing.message}"
                print(f"queued again #{weighing.id} {weighing.registration_number} (rejected before: {why})")
            elif weighing.state == "delivered":
                print(f"not sent again: #{weighing.id} was delivered as inspection {weighing.inspection_id}")
            else:
                print(f"already queued: #{weighing.id}")
    finally:
        outbox.close()
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
            "rejected": f"{w.http_status}: {w.message}; {retry_hint(w.id)}",
            "pending": f"{w.attempts} tries" + (f"; last: {w.message}" if w.message else ""),
        }[w.state]
        print(f"{w.state:<9} #{w.id:<5} {w.registration_number:<12} {detail}")
    counts = {
        state: sum(w.state == state for w in weighings) for state in ("delivered", "rejected", "pending")
    }
    print(", ".join(f"{n} {state}" for state, n in counts.items()))
    return EXIT_PENDING if counts["pending"] else EXIT_OK


class _DefaultsFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Shows each option's default, except where there is none to show (required, unset, a flag)."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        if action.default in (None, False, argparse.SUPPRESS) or action.required:
            return action.help
        return super()._get_help_string(action)


def _positive_id(text: str) -> int:
    value = text.removeprefix("#")
    if not (value.isascii() and value.isdigit()) or int(value) < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a queue id such as 3 or #3 (see: report)")
    return int(value)


def _common_options(parser: argparse.ArgumentParser, *, queue: str, url: str | None, here: bool) -> None:
    """--queue (and --url) before the sub-command or after it; after it, they keep a value given before."""
    parser.add_argument(
        "--queue",
        default=argparse.SUPPRESS if here else queue,
        help="the queue file (env TRIKECERT_STATION_QUEUE)" + (f" (default: {queue})" if here else ""),
    )
    if url is not None:
        parser.add_argument(
            "--url",
            default=argparse.SUPPRESS if here else url,
            help="the service's address (env TRIKECERT_STATION_URL)" + (f" (default: {url})" if here else ""),
        )


def _send_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--key-file", help="file holding the station key (else env TRIKECERT_STATION_KEY)")
    parser.add_argument(
        "--timeout",
        type=float,
        default=15.0,
        help="seconds to wait to connect, and for each part of an answer, before trying again",
    )
    parser.add_argument("--backoff-base", type=float, default=0.5, help="first retry delay, seconds")
    parser.add_argument(
        "--backoff-cap",
        type=float,
        default=60.0,
        help="longest retry delay, seconds (Retry-After may be longer)",
    )
    parser.add_argument(
        "--give-up-after",
        type=float,
        default=600.0,
        help="stop when the service has not answered for this many seconds (the rest stay queued)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The command line: queue, weigh, send, submit, retry, report."""
    queue_default = os.environ.get("TRIKECERT_STATION_QUEUE", "trikecert-station.db")
    url_default = os.environ.get("TRIKECERT_STATION_URL", "http://127.0.0.1:8000")
    parser = argparse.ArgumentParser(
        prog="trikecert-station",
        description="Deliver weighbridge weighings to trikecert exactly once.",
        formatter_class=_DefaultsFormatter,
    )
    _common_options(parser, queue=queue_default, url=url_default, here=False)
    commands = parser.add_subparsers(dest="command", required=True)

    def command(
        name: str, help_text: str, description: str, *, sends: bool = False
    ) -> argparse.ArgumentParser:
        sub = commands.add_parser(
            name, help=help_text, description=description, formatter_class=_DefaultsFormatter
        )
        _common_options(sub, queue=queue_default, url=url_default if sends else None, here=True)
        if sends:
            _send_options(sub)
        return sub

    queue = command(
        "queue",
        "queue the weighings of CSV or JSON files",
        "Queue the files' weighings on disk (a row queued before is not queued again); `send` sends them.",
    )
    queue.add_argument("files", nargs="+", help="CSV or JSON files of weighings")
    queue.set_defaults(handler=cmd_queue)

    weigh = command(
        "weigh",
        "queue one weighing read from a weighing indicator",
        "Read each wheel in turn from a weighing indicator and queue the weighing; `send` sends it.",
    )
    weigh.add_argument("--registration", required=True, help="the vehicle's registration number")
    weigh.add_argument(
        "--indicator", required=True, help="serial device (/dev/ttyUSB0), pty or file of lines"
    )
    weigh.add_argument(
        "--layout",
        choices=tuple(WHEEL_ORDER_WORDS),
        default="delta",
        help="the vehicle's axle layout, which sets the wheels to weigh and their order (default delta)",
    )
    weigh.add_argument("--repeat", type=int, default=1, help="stable readings per wheel")
    weigh.add_argument("--overall", action="store_true", help="then read the whole vehicle too")
    weigh.add_argument("--continuous", action="store_true", help="the indicator sends continuously")
    weigh.add_argument("--baud", type=int, default=9600, help="the serial line's speed, bit/s")
    weigh.add_argument(
        "--idle-timeout", type=float, default=60.0, help="give up after the indicator is silent this long, s"
    )
    weigh.set_defaults(handler=cmd_weigh)

    send = command(
        "send",
        "send every queued weighing",
        "Send every queued weighing, retrying with backoff until the service has answered each.",
        sends=True,
    )
    send.set_defaults(handler=cmd_send)

    submit = command(
        "submit",
        "queue the files' weighings, then send",
        "Queue the files' weighings, then send.",
        sends=True,
    )
    submit.add_argument("files", nargs="+", help="CSV or JSON files of weighings")
    submit.set_defaults(handler=cmd_submit)

    retry = command(
        "retry",
        "send rejected weighings again once their cause is fixed",
        "Put rejected weighings back in the queue (say, once the vehicle is registered or the scale's "
        "calibration renewed), then send everything queued. Ids are those of `report`.",
        sends=True,
    )
    retry.add_argument("ids", nargs="+", type=_positive_id, metavar="ID", help="queue ids, such as 3 or #3")
    retry.set_defaults(handler=cmd_retry)

    command(
        "report", "what was delivered, rejected, or is still queued", "List every weighing in the queue."
    ).set_defaults(handler=cmd_report)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script."""
    args = build_parser().parse_args(argv)
    try:
        code: int = args.handler(args)
    except SourceError as error:
        print(f"trikecert-station: {error}", file=sys.stderr)
        return EXIT_USAGE
    except sqlite3.Error as error:
        print(f"trikecert-station: the queue file {args.queue}: {error}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("trikecert-station: interrupted; every weighing not yet answered stays queued", file=sys.stderr)
        return EXIT_PENDING
    return code
