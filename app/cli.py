"""The `trikecert` command: serve, migrate, create-station, create-user, demo."""

from __future__ import annotations

import argparse
import getpass
import os
import sys
import tempfile
from collections.abc import Sequence

from app.config import get_settings
from app.db import get_engine, get_sessionmaker
from app.errors import ServiceError


def cmd_migrate(_args: argparse.Namespace) -> int:
    """Apply pending migrations."""
    from app.migrate import upgrade

    upgrade(get_engine())
    print(f"database at the newest revision: {get_engine().url.render_as_string(hide_password=True)}")
    return 0


def cmd_serve(args: argparse.Namespace) -> int:
    """Apply pending migrations (unless --no-migrate), then serve with uvicorn."""
    import uvicorn

    if not args.no_migrate:
        cmd_migrate(args)
    if args.workers > 1 and not os.environ.get("PROMETHEUS_MULTIPROC_DIR"):
        # Workers are separate processes: they share request metrics through files in this folder.
        os.environ["PROMETHEUS_MULTIPROC_DIR"] = tempfile.mkdtemp(prefix="trikecert-metrics-")
    uvicorn.run(
        "app.main:create_app", factory=True, host=args.host, port=args.port, workers=args.workers,
        proxy_headers=True, log_level="info", access_log=False,
    )
    return 0


def cmd_create_station(args: argparse.Namespace) -> int:
    """Create a station and print its key alone on the last line."""
    from app.stations.service import create_station

    with get_sessionmaker()() as session:
        station, key = create_station(session, name=args.name)
    print(f"station {station.id} {station.name!r} created; its API key is shown once, below:")
    print(key)
    return 0


def cmd_create_user(args: argparse.Namespace) -> int:
    """Create an officer or admin; the password is read from standard input."""
    from app.accounts.service import create_user

    if sys.stdin.isatty():
        password = getpass.getpass("Password: ")
    else:
        password = sys.stdin.readline().rstrip("\r\n")
    with get_sessionmaker()() as session:
        user = create_user(session, email=args.email, password=password, role=args.role)
    print(f"user {user.id} {user.email} ({user.role}) created")
    return 0


def cmd_demo(_args: argparse.Namespace) -> int:
    """Load the study's vehicle and inspection."""
    from app.demo import STUDY_REGISTRATION, load_demo
    from app.migrate import upgrade

    upgrade(get_engine())
    with get_sessionmaker()() as session:
        result = load_demo(session, get_settings())
    if not result.created or result.inspection is None:
        print(f"the demo vehicle {STUDY_REGISTRATION} is already loaded; nothing changed")
        return 0
    inspection = result.inspection
    print(f"loaded the study's vehicle {STUDY_REGISTRATION} and inspection {inspection.id}:")
    print(f"{'occupants':>9} {'total kg':>9} {'rear kg':>8} {'LSF':>6} {'variance':>8}  result")
    for case in inspection.loading_cases:
        verdict = "C" if case.compliant else "NC"
        print(
            f"{case.occupants:>9} {case.total_kg:>9.1f} {case.rear_kg:>8.2f} {case.lsf:>6.3f} "
            f"{case.variance:>+8.3f}  {verdict}"
        )
    print(f"compliant: {inspection.compliant}; max compliant occupants: {inspection.max_compliant_occupants}")
    print("demo station key (shown once):")
    print(result.station_key)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The command line: one sub-command per job."""
    parser = argparse.ArgumentParser(prog="trikecert", description="Lateral stability certification service.")
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
    station.set_defaults(handler=cmd_create_station)

    user = commands.add_parser("create-user", help="create an account (password from standard input)")
    user.add_argument("email")
    user.add_argument("--role", choices=["officer", "admin"], required=True)
    user.set_defaults(handler=cmd_create_user)

    commands.add_parser("demo", help="load the study's vehicle and its inspection").set_defaults(handler=cmd_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script."""
    args = build_parser().parse_args(argv)
    try:
        code: int = args.handler(args)
    except ServiceError as error:
        print(f"trikecert: {error.message}", file=sys.stderr)
        return 2
    return code


if __name__ == "__main__":
    raise SystemExit(main())
