"""Load benchmark: trikecert beside its yardsticks, side by side in one run, on SQLite and PostgreSQL.

Run by hand (needs Debian's wrk and a local PostgreSQL):  .venv/bin/python bench/load.py
Options: --backends sqlite,postgresql --workers 2 --duration 10 --connections 32 --rounds 2
         --label NAME --also NAME=CHECKOUT (repeatable)

Per backend, three servers run at once with the same worker count on one fresh database:
trikecert (`trikecert serve`), the naive peer and the bare Starlette route (bench/peer.py). Each
round loads, one after the other: the bare route and trikecert's /healthz; the peer's POST and
trikecert's POST /api/v1/inspections, without and with an Idempotency-Key. Rounds repeat the
sequence, so a change in the machine's load falls on every target alike. Each row gives the
server's CPU (and PostgreSQL's) per answered request and the machine's load average.

`--public` loads the public doors instead of the POSTs, in the same rounds beside the same yardsticks
(the bare route and /healthz): one certificate is issued, then its HTML `/verify/{number}`, the JSON
verification (`/api/v1/verify/{number}`), the published key list and the trust bundle's conditional GET
(`If-None-Match` with its ETag: 304). The public rate limit stays on, counted, but too high to refuse:

    .venv/bin/python bench/load.py --backends sqlite --connections 16 --public

Two versions of trikecert in one run: `--also NAME=CHECKOUT` serves another checkout too (its own
`CHECKOUT/.venv`, same workers, same database, migrated and seeded by this one, so both must be at
the same migration), and loads its POSTs, without and with a key, right after this checkout's in
every round; `--label NAME` names this checkout's rows (default: trikecert).
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import secrets
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PG_SERVER = os.environ.get("TRIKECERT_BENCH_PG", "postgresql+psycopg://postgres@127.0.0.1:5432/test")
VEHICLES = 20


def free_port() -> int:
    """A TCP port nobody listens on."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def fresh_database(backend: str, scratch: Path) -> str:
    """A new empty database URL for the backend."""
    if backend == "sqlite":
        return f"sqlite:///{scratch / 'bench.db'}"
    return new_postgres_database("trikecert_bench")


def new_postgres_database(prefix: str) -> str:
    """Create an empty database with a random name on the benchmark server; its URL."""
    from sqlalchemy import create_engine, text
    from sqlalchemy.engine import make_url

    name = f"{prefix}_{secrets.token_hex(4)}"
    admin = create_engine(PG_SERVER, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'CREATE DATABASE "{name}"'))
    admin.dispose()
    return make_url(PG_SERVER).set(database=name).render_as_string(hide_password=False)


def drop_database(url: str) -> None:
    """Drop a benchmark database made by fresh_database."""
    from sqlalchemy import create_engine, text
    from sqlalchemy.engine import make_url

    admin = create_engine(PG_SERVER, isolation_level="AUTOCOMMIT")
    with admin.connect() as connection:
        connection.execute(text(f'DROP DATABASE IF EXISTS "{make_url(url).database}" WITH (FORCE)'))
    admin.dispose()


def seed(env: dict[str, str]) -> str:
    """Migrate, create a station and the benchmark vehicles; return the station key."""
    code = f"""
from decimal import Decimal
from app.db import get_engine, get_sessionmaker
from app.migrate import upgrade
from app.stations.service import create_station
from app.vehicles.service import register_vehicle
upgrade(get_engine())
with get_sessionmaker()() as s:
    _, key = create_station(s, name="bench")
    for i in range({VEHICLES}):
        register_vehicle(s, registration_number=f"BEN {{i:04d}}", make="Bajaj", model="RE",
            wheelbase_m=Decimal("2.000"),
            seats=[("driver", Decimal("0.9303"))] + [("passenger", Decimal("1.6303"))] * 3)
print(key)
"""
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return out.stdout.strip().splitlines()[-1]


# A load: its row's name, the server, the URL, a wrk script, wrk's environment, extra request headers.
Target = tuple[str, str, str, str | None, dict[str, str], tuple[str, ...]]


def public_paths(base: str, key: str) -> dict[str, tuple[str, str | None]]:
    """Issue one certificate through the API; the public doors to load: name -> (path, If-None-Match)."""

    def call(method: str, path: str, body: bytes | None = None) -> urllib.request.addinfourl:
        headers = {"Authorization": f"Bearer {key}", "Content-Type": "application/json"}
        request = urllib.request.Request(base + path, data=body, method=method, headers=headers)
        return urllib.request.urlopen(request, timeout=30)

    import json

    body = json.dumps(
        {
            "registration_number": "BEN 0000",
            "readings": {"front_kg": 200, "left_rear_kg": 80, "right_rear_kg": 80},
        }
    ).encode()
    inspection = json.load(call("POST", "/api/v1/inspections", body))["id"]
    number = json.load(call("POST", f"/api/v1/inspections/{inspection}/certificate"))["number"]
    etag = call("GET", "/.well-known/trikecert-trust").headers["ETag"]
    return {
        "GET /verify/{number} (HTML)": (f"/verify/{number}", None),
        "GET /api/v1/verify/{number}": (f"/api/v1/verify/{number}", None),
        "GET /.well-known/trikecert-keys.json": ("/.well-known/trikecert-keys.json", None),
        "GET /.well-known/trikecert-trust, If-None-Match (304)": ("/.well-known/trikecert-trust", etag),
    }


def wait_ready(port: int) -> None:
    """Poll /readyz until the server answers 200."""
    wait_answering(port, "/readyz")


def parse_wrk(output: str) -> tuple[float, str, str, int]:
    """Requests/s, p50, p99 and the non-2xx count from wrk --latency output."""
    rate = float(re.search(r"Requests/sec:\s+([\d.]+)", output).group(1))  # type: ignore[union-attr]
    p50 = re.search(r"\s50%\s+(\S+)", output).group(1)  # type: ignore[union-attr]
    p99 = re.search(r"\s99%\s+(\S+)", output).group(1)  # type: ignore[union-attr]
    errors = re.search(r"non-2xx/3xx: (\d+)", output)
    non2xx = re.search(r"Non-2xx or 3xx responses: (\d+)", output)
    bad = int(errors.group(1)) if errors else int(non2xx.group(1)) if non2xx else 0
    return rate, p50, p99, bad


def wrk(
    url: str,
    connections: int,
    duration: int,
    env: dict[str, str],
    script: str | None = None,
    headers: tuple[str, ...] = (),
) -> str:
    """Run wrk (2 threads) and return its output."""
    command = ["wrk", "-t2", f"-c{connections}", f"-d{duration}s", "--latency", url]
    for header in headers:
        command[1:1] = ["-H", header]
    if script:
        command[1:1] = ["-s", script]
    return subprocess.run(command, env=env, capture_output=True, text=True, check=True).stdout


def _descendants(pid: int) -> list[int]:
    """The process and all its children, recursively (the uvicorn workers of `trikecert serve`)."""
    found = [pid]
    for task in Path(f"/proc/{pid}/task").glob("*/children"):
        for child in task.read_text().split():
            found += _descendants(int(child))
    return found


def _postgres_pids() -> list[int]:
    return [int(p.parent.name) for p in Path("/proc").glob("[0-9]*/comm") if _read(p).strip() == "postgres"]


def _read(path: Path) -> str:
    try:
        return path.read_text()
    except OSError:  # the process ended meanwhile
        return ""


def cpu_seconds(pids: list[int]) -> float:
    """User + system CPU seconds the processes have used so far (from /proc/PID/stat)."""
    ticks = 0
    for pid in pids:
        fields = _read(Path(f"/proc/{pid}/stat")).rpartition(")")[2].split()
        if fields:
            ticks += int(fields[11]) + int(fields[12])  # utime, stime
    return ticks / os.sysconf("SC_CLK_TCK")


def measured(
    url: str,
    connections: int,
    args: argparse.Namespace,
    env: dict[str, str],
    server: int,
    script: str | None,
    headers: tuple[str, ...] = (),
) -> tuple[tuple[float, str, str, int], float, float]:
    """wrk's figures, and the server's and PostgreSQL's CPU milliseconds per answered request."""
    app_before, db_before = cpu_seconds(_descendants(server)), cpu_seconds(_postgres_pids())
    result = parse_wrk(wrk(url, connections, args.duration, env, script=script, headers=headers))
    requests = max(1.0, result[0] * args.duration)
    app_ms = 1000 * (cpu_seconds(_descendants(server)) - app_before) / requests
    db_ms = 1000 * (cpu_seconds(_postgres_pids()) - db_before) / requests
    return result, app_ms, db_ms


def start(command: list[str], env: dict[str, str], cwd: Path | None = None) -> subprocess.Popen[bytes]:
    """A server process, its output discarded."""
    return subprocess.Popen(command, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def also_served(option: str) -> tuple[str, Path]:
    """--also NAME=CHECKOUT: the name of another checkout's rows and its `trikecert` command."""
    name, equals, checkout = option.partition("=")
    command = Path(checkout).resolve() / ".venv/bin/trikecert"
    if not (name and equals and command.is_file()) or name in ("trikecert", "peer", "bare"):
        raise SystemExit(
            f"--also {option}: expected NAME=CHECKOUT, NAME not trikecert, peer or bare, "
            "with CHECKOUT/.venv/bin/trikecert"
        )
    return name, command


def wait_answering(port: int, path: str) -> None:
    """Poll a GET path until it answers 200."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=2) as response:
                if response.status == 200:
                    return
        except OSError:
            time.sleep(0.2)
    raise RuntimeError(f"nothing answered on port {port}")


def run_backend(backend: str, args: argparse.Namespace) -> list[str]:
    """Start a server on the backend, run every load, and return markdown table rows."""
    scratch = Path(tempfile.mkdtemp(prefix="trikecert-bench-"))
    # The rate limit stays on (its counter is bumped on every request, as in production) but so high
    # that no request of the run is refused.
    env = dict(
        os.environ,
        TRIKECERT_DATABASE_URL=fresh_database(backend, scratch),
        TRIKECERT_ENVIRONMENT="test",
        TRIKECERT_STATION_RATE_LIMIT="1000000000",
        TRIKECERT_PUBLIC_RATE_LIMIT="1000000000",
        TRIKECERT_SIGNING_KEY_FILE=str(scratch / "signing-key.pem"),
    )
    key = seed(env)
    sys.path.insert(0, str(ROOT / "bench"))
    from peer import create_table

    create_table(env["TRIKECERT_DATABASE_URL"])
    bin_dir = Path(sys.executable).parent
    also = dict(also_served(option) for option in args.also)
    ports = {name: free_port() for name in ("trikecert", "peer", "bare", *also)}
    workers = ["--workers", str(args.workers)]

    def serve(command: Path, port: int, cwd: Path) -> subprocess.Popen[bytes]:
        return start([str(command), "serve", "--port", str(port), *workers, "--no-migrate"], env, cwd)

    uvicorn = [str(bin_dir / "uvicorn"), "--app-dir", str(ROOT / "bench"), "--no-access-log", *workers]
    peer_env = dict(env, PEER_DATABASE_URL=env["TRIKECERT_DATABASE_URL"])
    servers = {
        "trikecert": serve(bin_dir / "trikecert", ports["trikecert"], ROOT),
        "peer": start([*uvicorn, "--port", str(ports["peer"]), "peer:peer_app"], peer_env),
        "bare": start([*uvicorn, "--port", str(ports["bare"]), "peer:bare_app"], env),
        **{name: serve(command, ports[name], command.parents[2]) for name, command in also.items()},
    }
    rows = []
    try:
        for name in ("trikecert", *also):
            wait_ready(ports[name])
        wait_answering(ports["bare"], "/healthz")
        wrk_env = dict(env, TRIKECERT_BENCH_KEY=key, TRIKECERT_BENCH_VEHICLES=str(VEHICLES))
        script = str(ROOT / "bench/post_inspection.lua")
        url = {name: f"http://127.0.0.1:{port}" for name, port in ports.items()}
        keyed_env = dict(wrk_env, TRIKECERT_BENCH_IDEMPOTENCY="1")
        label = {"trikecert": args.label, **{name: name for name in also}}
        targets: list[Target] = [
            ("bare Starlette GET /healthz", "bare", f"{url['bare']}/healthz", None, wrk_env, ()),
            (f"{args.label} GET /healthz", "trikecert", f"{url['trikecert']}/healthz", None, wrk_env, ()),
        ]
        if args.public:
            doors = public_paths(url["trikecert"], key)
            targets += [
                (
                    f"{args.label} {name}",
                    "trikecert",
                    url["trikecert"] + path,
                    None,
                    wrk_env,
                    () if etag is None else (f"If-None-Match: {etag}",),
                )
                for name, (path, etag) in doors.items()
            ]
        else:
            targets += [
                ("peer POST (one row)", "peer", url["peer"], script, wrk_env, ()),
                *[
                    (f"{label[name]} POST", name, url[name], script, wrk_env, ())
                    for name in ("trikecert", *also)
                ],
                *[
                    (f"{label[name]} POST + Idempotency-Key", name, url[name], script, keyed_env, ())
                    for name in ("trikecert", *also)
                ],
            ]
        for connections in args.connections:
            for round_number in range(1, args.rounds + 1):
                for name, server, target, lua, target_env, headers in targets:
                    result, app_ms, db_ms = measured(
                        target, connections, args, target_env, servers[server].pid, lua, headers
                    )
                    load = os.getloadavg()[0]  # other work on the machine skews every figure: show it
                    db = f"{db_ms:.2f}" if backend == "postgresql" else "(in app)"
                    rows.append(
                        f"| {backend} | {connections} | {round_number} | {name} | {result[0]:.0f} | "
                        f"{result[1]} / {result[2]} | {result[3]} | {app_ms:.2f} | {db} | {load:.1f} |"
                    )
                    print(rows[-1], flush=True)
    finally:
        for process in servers.values():
            process.terminate()
        for process in servers.values():
            process.wait(timeout=30)
        shutil.rmtree(scratch, ignore_errors=True)
        if backend == "postgresql":
            drop_database(env["TRIKECERT_DATABASE_URL"])
    return rows


def main() -> None:
    """Parse options, run each backend, print the results table."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--backends", default="sqlite,postgresql")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--duration", type=int, default=10)
    parser.add_argument("--connections", default="32")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--label", default="trikecert", help="the name of this checkout's rows")
    parser.add_argument(
        "--public",
        action="store_true",
        help="load the public doors (/verify, the JSON verification, the key list, the bundle's 304) "
        "instead of the POSTs",
    )
    parser.add_argument(
        "--also",
        action="append",
        default=[],
        metavar="NAME=CHECKOUT",
        help="serve another trikecert checkout (its own .venv) too, on the same database, and load its POSTs",
    )
    args = parser.parse_args()
    args.connections = [int(c) for c in args.connections.split(",")]
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"server workers: {args.workers}; wrk -t2 -d{args.duration}s on the same cores"
    )
    print(
        "| backend | connections | round | target | req/s | p50 / p99 | non-2xx | server CPU ms per "
        "request | PostgreSQL CPU ms per request | load avg (1 min) |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for backend in args.backends.split(","):
        run_backend(backend, args)


if __name__ == "__main__":
    main()
