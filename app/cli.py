"""The `trikecert` command: serve, migrate, stations, create-user, demo, prune-idempotency-keys."""

from __future__ import annotations

import argparse
import getpass
import logging
import os
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import replace
from datetime import date
from decimal import Decimal, InvalidOperation

from pydantic import ValidationError
from sqlalchemy.exc import DBAPIError

import app.models  # noqa: F401  (every table and the audit recorder: a command writes records too)
from app import __version__
from app.audit.recorder import acting_from_command_line
from app.certificates.cli import add_certificate_commands
from app.cli_values import dash_safe
from app.config import get_settings, settings_problems, trusted_proxies
from app.db import get_engine, get_sessionmaker, is_outage
from app.errors import ServiceError
from app.stations.details import StationDetails, details_of
from app.stations.models import Station
from app.wording import verdict_mark


def cmd_migrate(_args: argparse.Namespace) -> int:
    """Apply pending migrations."""
    from app.migrate import upgrade

    role = upgrade(get_engine())
    print(f"database at the newest revision: {get_engine().url.render_as_string(hide_password=True)}")
    if role is not None:
        print(f"app role {role}: may read and append to the records, never change them")
    return 0


def cmd_serve(args: argparse.Namespace) -> int:
    """Apply pending migrations (unless --no-migrate), then serve with uvicorn."""
    import uvicorn

    if not args.no_migrate:
        cmd_migrate(args)
    if args.workers > 1 and not os.environ.get("PROMETHEUS_MULTIPROC_DIR"):
        # Workers are separate processes: they share request metrics through files in this folder.
        os.environ["PROMETHEUS_MULTIPROC_DIR"] = tempfile.mkdtemp(prefix="trikecert-metrics-")
    from app.audit.startup import record_start

    with get_sessionmaker()() as session:
        record_start(session, get_settings())
    proxies = trusted_proxies(get_settings().forwarded_allow_ips)
    from app.ops.slow_clients import guarded_protocol

    uvicorn.run(
        "app.main:create_served_app",
        factory=True,
        # uvicorn's own parser, with deadlines for a request's headers and body (slow clients).
        http=guarded_protocol(),
        host=args.host,
        port=args.port,
        workers=args.workers,
        # uvicorn kills a worker that has not answered its supervisor's ping in 5 s; a worker still
        # importing on a busy host is not hung, so it gets longer before it is killed and restarted.
        timeout_worker_healthcheck=30,
        # X-Forwarded-Proto/-For count only from the proxies named in TRIKECERT_FORWARDED_ALLOW_IPS.
        proxy_headers=bool(proxies),
        forwarded_allow_ips=proxies or None,
        server_header=False,
        log_level="info",
        access_log=False,
    )
    return 0


def _date(text: str) -> date:
    try:
        return date.fromisoformat(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"give a date as YYYY-MM-DD, not {text!r}") from error


def _kg(text: str) -> Decimal:
    try:
        value = Decimal(text)
    except InvalidOperation as error:
        raise argparse.ArgumentTypeError(f"give a number of kg, not {text!r}") from error
    return value


_DETAIL_OPTIONS = {
    "location": "location",
    "contact": "operator_contact",
    "calibration_certificate": "calibration_certificate",
    "calibration_valid_until": "calibration_valid_until",
    "capacity_kg": "capacity_kg",
    "division_kg": "division_kg",
}


def _details(args: argparse.Namespace, current: StationDetails | None = None) -> StationDetails:
    """The station details from the options given, keeping the current ones for options left out."""
    given = {field: getattr(args, option) for option, field in _DETAIL_OPTIONS.items()}
    return replace(current or StationDetails(), **{k: v for k, v in given.items() if v is not None})


def _print_station(station: Station) -> None:
    calibration = (
        f"calibration {station.calibration_certificate or '-'} valid until {station.calibration_valid_until}"
        if station.calibration_valid_until
        else "no calibration on record"
    )
    state = "active" if station.active else "disabled"
    print(
        f"station {station.id} {station.name!r} ({state}): {calibration}; "
        f"capacity {station.capacity_kg or '-'} kg, division {station.division_kg or '-'} kg"
    )


def cmd_create_station(args: argparse.Namespace) -> int:
    """Create a station and print its key alone on the last line."""
    from app.stations.service import create_station

    with get_sessionmaker()() as session:
        station, key = create_station(session, name=args.name, details=_details(args))
    print(f"station {station.id} {station.name!r} created; its API key is shown once, below:")
    print(key)
    return 0


def cmd_update_station(args: argparse.Namespace) -> int:
    """Change a station's particulars (only the options given); its key stays as it is."""
    from app.stations.service import find_station, update_station

    with get_sessionmaker()() as session:
        station = find_station(session, args.station)
        update_station(session, station=station, details=_details(args, details_of(station)), name=args.name)
        _print_station(station)
    return 0


def cmd_rotate_station_key(args: argparse.Namespace) -> int:
    """Give a station a new key (the old one stops working) and print it alone on the last line."""
    from app.stations.service import find_station, rotate_key

    with get_sessionmaker()() as session:
        station = find_station(session, args.station)
        key = rotate_key(session, station=station)
    print(f"station {station.id} {station.name!r} has a new API key; the old one no longer works:")
    print(key)
    return 0


def cmd_set_station_active(args: argparse.Namespace) -> int:
    """Disable a station (its key is refused) or enable it again."""
    from app.stations.service import find_station, set_station_active

    with get_sessionmaker()() as session:
        station = find_station(session, args.station)
        set_station_active(session, station=station, active=args.active)
        _print_station(station)
    return 0


def cmd_prune_idempotency_keys(args: argparse.Namespace) -> int:
    """Delete idempotency keys older than the retention (at least 24 hours)."""
    from datetime import timedelta

    from app.db import utcnow
    from app.idempotency.service import prune

    hours = max(24, args.older_than_hours or get_settings().idempotency_key_hours)
    with get_engine().connect() as connection:
        count = prune(connection, older_than=utcnow() - timedelta(hours=hours))
    print(f"deleted {count} idempotency key(s) older than {hours} hours")
    return 0


def cmd_count_statistics(args: argparse.Namespace) -> int:
    """Store the counts of the closed days of the last --days days in the display zone (a nightly job)."""
    from datetime import UTC, timedelta

    from app.db import utcnow
    from app.statistics.service import MAX_DAYS
    from app.statistics.stored import count_closed_days, last_closed_day
    from app.web.formatting import local_zone

    zone = local_zone() or UTC
    last = last_closed_day(zone, utcnow())
    counted, first = 0, last - timedelta(days=args.days - 1)
    with get_sessionmaker()() as session:
        while first <= last:  # a year at a time: one statement's worth of days
            chunk_last = min(last, first + timedelta(days=MAX_DAYS - 1))
            counted += count_closed_days(session, zone=zone, first=first, last=chunk_last)
            first = chunk_last + timedelta(days=1)
    print(f"counted {counted} closed day(s) not stored before, up to {last.isoformat()}")
    return 0


def cmd_create_user(args: argparse.Namespace) -> int:
    """Create an officer or admin; the password is read from standard input."""
    from app.accounts.service import create_user

    if sys.stdin.isatty():
        password = getpass.getpass("Password: ")
    else:
        password = sys.stdin.readline().rstrip("\r\n")
    with get_sessionmaker()() as session:
        user = create_user(
            session, email=args.email, password=password, role=args.role, name=args.name, badge=args.badge
        )
    print(f"user {user.id} {user.email} ({user.role}) created: {user.shown_as()}")
    if get_settings().mfa_mode() == "required":
        print("at the first sign-in they set up a second factor: an authenticator app on their phone")
    else:
        print(
            "second factor optional here (TRIKECERT_MFA=optional): they may set one up at /account/two-factor"
        )
    return 0


def cmd_demo(_args: argparse.Namespace) -> int:
    """Load the study's vehicle and inspection."""
    from app.demo import DEMO_STATION, STUDY_REGISTRATION, load_demo
    from app.migrate import upgrade
    from app.web.formatting import load_kg

    upgrade(get_engine())
    with get_sessionmaker()() as session:
        result = load_demo(session, get_settings())
    if not result.created or result.inspection is None:
        print(f"the demo vehicle {STUDY_REGISTRATION} is already loaded; nothing changed")
        print(
            "the demo station's key was shown once, when it was made; for a new one "
            f"(the old one stops working): trikecert rotate-station-key '{DEMO_STATION}'"
        )
        return 0
    inspection = result.inspection
    print(f"loaded the study's vehicle {STUDY_REGISTRATION} and inspection {inspection.id}:")
    print(f"{'occupants':>9} {'total kg':>9} {'rear kg':>8} {'LSF':>6} {'variance':>8}  result")
    for case in inspection.loading_cases:
        verdict = verdict_mark(case.compliant)
        print(
            f"{case.occupants:>9} {load_kg(case.total_kg):>9} {load_kg(case.rear_kg):>8} {case.lsf:>6.3f} "
            f"{case.variance:>+8.3f}  {verdict}"
        )
    print(f"compliant: {inspection.compliant}; max compliant occupants: {inspection.max_compliant_occupants}")
    print("demo station key (shown once):")
    print(result.station_key)
    return 0


def _station_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--location", help="where the weighbridge stands")
    parser.add_argument("--contact", help="the operator's name, phone or email")
    parser.add_argument("--calibration-certificate", help="the scale's calibration certificate number")
    parser.add_argument(
        "--calibration-valid-until", type=_date, help="last day the calibration is valid (YYYY-MM-DD)"
    )
    parser.add_argument("--capacity-kg", type=_kg, help="the scale's capacity (Max), kg")
    parser.add_argument("--division-kg", type=_kg, help="the scale's division (e), kg")


def build_parser() -> argparse.ArgumentParser:
    """The command line: one sub-command per job."""
    parser = argparse.ArgumentParser(prog="trikecert", description="Lateral stability certification service.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True)

    serve = commands.add_parser("serve", help="apply migrations, then serve HTTP")
    serve.add_argument("--host", default="127.0.0.1")
    serve.add_argument("--port", type=int, default=8000)
    serve.add_argument("--workers", type=int, default=1)
    serve.add_argument(
        "--no-migrate", action="store_true", help="skip migrations (a separate one-shot `migrate` runs them)"
    )
    serve.set_defaults(handler=cmd_serve)

    commands.add_parser("migrate", help="apply pending migrations").set_defaults(handler=cmd_migrate)

    station = commands.add_parser("create-station", help="create a weighbridge station and print its key")
    station.add_argument("name")
    _station_options(station)
    station.set_defaults(handler=cmd_create_station)

    update = commands.add_parser("update-station", help="change a station's particulars or its scale's")
    update.add_argument("station", help="the station's name (or id)")
    update.add_argument("--name", help="a new name")
    _station_options(update)
    update.set_defaults(handler=cmd_update_station)

    rotate = commands.add_parser(
        "rotate-station-key", help="give a station a new key; the old one stops working"
    )
    rotate.add_argument("station", help="the station's name (or id)")
    rotate.set_defaults(handler=cmd_rotate_station_key)

    disable = commands.add_parser("disable-station", help="refuse a station's key until it is enabled again")
    disable.add_argument("station", help="the station's name (or id)")
    disable.set_defaults(handler=cmd_set_station_active, active=False)

    enable = commands.add_parser("enable-station", help="accept a disabled station's key again")
    enable.add_argument("station", help="the station's name (or id)")
    enable.set_defaults(handler=cmd_set_station_active, active=True)

    prune = commands.add_parser("prune-idempotency-keys", help="delete idempotency keys past their retention")
    prune.add_argument(
        "--older-than-hours", type=int, help="default TRIKECERT_IDEMPOTENCY_KEY_HOURS; at least 24"
    )
    prune.set_defaults(handler=cmd_prune_idempotency_keys)

    count = commands.add_parser(
        "count-statistics", help="store the statistics of closed days (else done on the first visit)"
    )
    count.add_argument(
        "--days", type=int, default=366, help="how many days back from yesterday (default 366)"
    )
    count.set_defaults(handler=cmd_count_statistics)

    user = commands.add_parser("create-user", help="create an account (password from standard input)")
    user.add_argument("email")
    user.add_argument("--role", choices=["officer", "admin"], required=True)
    user.add_argument("--name", required=True, help="the person's name, as certificates print it")
    user.add_argument("--badge", help="the officer's badge number (optional)")
    user.set_defaults(handler=cmd_create_user)

    audit = commands.add_parser(
        "audit-verify",
        help="check that no audit event was changed, removed or inserted since it was recorded",
    )
    audit.set_defaults(handler=cmd_audit_verify)

    notify = commands.add_parser(
        "notify", help="send the reminders and replies in the outbox (SMS gateway, SMTP); runs until stopped"
    )
    notify.add_argument("--once", action="store_true", help="one pass, then exit")
    notify.set_defaults(handler=cmd_notify)

    demo = commands.add_parser("demo", help="load the study's vehicle and its inspection")
    demo.set_defaults(handler=cmd_demo)
    add_certificate_commands(commands)
    return parser


def cmd_notify(args: argparse.Namespace) -> int:
    """Plan the reminders due and send the outbox: email over SMTP when TRIKECERT_SMTP_URL is set, SMS
    through Africa's Talking when TRIKECERT_AFRICASTALKING_API_KEY is (a channel without one waits)."""
    from app.gateway.africastalking import AfricasTalkingSender
    from app.notifications.worker import Sender, SmtpSender, run

    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s %(levelname)s %(message)s")
    settings = get_settings()
    senders: dict[str, Sender] = {}
    if settings.smtp_url is not None:
        senders["email"] = SmtpSender(
            settings.smtp_url.get_secret_value(), settings.mail_from, settings.notify_timeout_seconds
        )
    if settings.africastalking_api_key is not None:
        senders["sms"] = AfricasTalkingSender(settings)
    if not senders:
        print(
            "trikecert notify: neither TRIKECERT_SMTP_URL nor TRIKECERT_AFRICASTALKING_API_KEY is set",
            file=sys.stderr,
        )
    try:
        run(get_sessionmaker(), senders, settings, once=args.once)
    except KeyboardInterrupt:
        return 0
    return 0


def cmd_audit_verify(_args: argparse.Namespace) -> int:
    """Check the audit log's hash chain from the first event and sign its head; exit 1 when it was
    tampered with."""
    from app.audit_log.checkpoint import record_checkpoint
    from app.audit_log.service import verify_log

    with get_sessionmaker()() as session:
        report = verify_log(session)
        intact = report.intact and report.events > 0
        checkpoint = record_checkpoint(session, get_settings(), event_id=report.events) if intact else None
    if report.intact:
        print(f"the audit log is intact: {report.events} events checked")
        if checkpoint is not None:
            print(f"checkpoint {checkpoint.id} signed at event {checkpoint.event_id}: {checkpoint.hash}")
        return 0
    print(f"the audit log was tampered with: {report.reason} ({report.events} events before it are intact)")
    return 1


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script."""
    parser = build_parser()
    args = parser.parse_args(dash_safe(parser, sys.argv[1:] if argv is None else argv))
    try:
        get_settings()
    except ValidationError as error:
        for line in settings_problems(error):
            print(f"trikecert: refusing to start: {line}", file=sys.stderr)
        return 2
    try:
        with acting_from_command_line():
            code: int = args.handler(args)
    except ServiceError as error:
        print(f"trikecert: {error.message}", file=sys.stderr)
        return 2
    except DBAPIError as error:
        problem = database_problem(error)
        if problem is None:
            raise
        print(f"trikecert: {problem}", file=sys.stderr)
        return 2
    return code


def database_problem(error: DBAPIError) -> str | None:
    """What an operator must do about a database error a command met, or None for a fault of the code
    (its traceback is what a maintainer needs)."""
    # Alembic (a tenth of a second) is read only when a command meets a database error.
    from app.migrate import is_at_head

    try:
        migrated = is_at_head(get_engine())
    except DBAPIError as unanswered:
        return _not_answering(unanswered)
    if not migrated:
        return "the database is not migrated to this version: run `trikecert migrate` first"
    return _not_answering(error) if is_outage(error) else None


def _not_answering(error: DBAPIError) -> str:
    said = str(error.orig).strip() or type(error).__name__
    return f"the database did not answer ({said.splitlines()[0]}); check that it runs, then try again"


if __name__ == "__main__":
    raise SystemExit(main())
