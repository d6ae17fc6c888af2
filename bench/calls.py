"""What one submission costs, counted rather than timed: statements, commits and Python calls.

Run by hand:  .venv/bin/python bench/calls.py [--backend sqlite|postgresql] [--requests 200]

Runs the app in-process (TestClient) on a fresh database with the load benchmark's bodies, and for
`--requests` submissions (after a warm-up) counts the SQL statements sent (an executemany counts as
one round trip), the commits, and the Python function calls (cProfile's count), each per request,
with and without an Idempotency-Key, and GET /healthz for the client's own share. Counts do not
depend on how loaded the machine is, which the rates and CPU times of a shared machine do.
"""

from __future__ import annotations

import argparse
import collections
import os
import shutil
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from load import ROOT, VEHICLES, drop_database, fresh_database, seed


def body(n: int) -> dict[str, Any]:
    """The load benchmark's body (bench/post_inspection.lua) for request n."""
    front = round(108 + (n % 5) * 0.1, 1)
    return {
        "registration_number": f"BEN {n % VEHICLES:04d}",
        "readings": {
            "front_kg": [front] * 3,
            "left_rear_kg": [115.0, 115.2, 114.8],
            "right_rear_kg": [135.0, 134.8, 135.2],
            "overall_kg": 359,
        },
    }


def package(filename: str) -> str:
    """The top-level package of a source file: sqlalchemy, app, ... ('other' for the standard library)."""
    if "/site-packages/" in filename:
        return filename.split("/site-packages/", 1)[1].split("/", 1)[0].removesuffix(".py")
    if f"{ROOT}/app/" in filename:
        return "app (trikecert)"
    return "standard library and other"


def innermost_app_line(frame: Any) -> str:
    """The innermost line of trikecert's own code on the stack (the step a call is made for)."""
    while frame is not None:
        if f"{ROOT}/app/" in frame.f_code.co_filename:
            where = frame.f_code.co_filename.split("/app/", 1)[1]
            return f"{frame.f_code.co_name} (app/{where}:{frame.f_lineno})"
        frame = frame.f_back
    return "outside trikecert"


class CallCounter:
    """Counts Python function calls in every thread (the app runs in TestClient's and the pool's)."""

    def __init__(self) -> None:
        self.calls = 0
        self.counting = False
        self.by_package: collections.Counter[str] = collections.Counter()
        self.by_step: collections.Counter[str] = collections.Counter()

    def __call__(self, frame: Any, event: str, _arg: Any) -> None:
        if self.counting and event in ("call", "c_call"):
            self.calls += 1
            self.by_package[package(frame.f_code.co_filename)] += 1  # a builtin: its caller's
            if BY_STEP:
                self.by_step[innermost_app_line(frame)] += 1

    def install(self) -> None:
        """Hook this thread and every thread started from now on."""
        sys.setprofile(self)
        threading.setprofile(self)


CALLS = CallCounter()
SHOW = bool(os.environ.get("TRIKECERT_BENCH_SHOW_SQL"))
BY_STEP = bool(os.environ.get("TRIKECERT_BENCH_BY_STEP"))  # also count calls by the app line they serve


def count(requests: int, send: Callable[[int], Any]) -> dict[str, float]:
    """Statements, commits, Python calls and in-process CPU ms per request of `send(n)`."""
    from sqlalchemy import Engine, event

    engine = Engine  # every engine: the app's and the peer's
    seen = {"statements": 0, "commits": 0}

    def statement(_connection: Any, _cursor: Any, sql: str, *_args: Any) -> None:
        seen["statements"] += 1
        if SHOW:
            print("   ", " ".join(sql.split())[:150], file=sys.stdout)

    def commit(*_args: Any) -> None:
        seen["commits"] += 1

    event.listen(engine, "before_cursor_execute", statement)
    event.listen(engine, "commit", commit)
    # The hot path's prepared statements go to the driver directly, past the cursor events.
    from app.prepared import Prepared

    run = Prepared._run

    def counted_run(self: Prepared, connection: Any, parameters: Any, *, many: bool) -> Any:
        statement(connection, None, self.sql)
        return run(self, connection, parameters, many=many)

    Prepared._run = counted_run  # type: ignore[method-assign]
    for n in range(20):  # warm-up: caches, pool, compiled statements
        send(n)
    seen.update(statements=0, commits=0)
    for n in range(requests):
        send(1000 + n)
    CALLS.calls, CALLS.counting = 0, True
    CALLS.by_package.clear()
    CALLS.by_step.clear()
    for n in range(requests):
        send(2000 + n)
    CALLS.counting = False
    event.remove(engine, "before_cursor_execute", statement)
    event.remove(engine, "commit", commit)
    Prepared._run = run  # type: ignore[method-assign]
    return {
        "statements": seen["statements"] / requests / 2,
        "commits": seen["commits"] / requests / 2,
        "calls": CALLS.calls / requests,
        **{f"calls in {name}": n / requests for name, n in CALLS.by_package.items()},
        **{f"step {name}": n / requests for name, n in CALLS.by_step.most_common(25)},
    }


def main() -> None:
    """Seed, count, print a markdown table."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--backend", default="sqlite", choices=["sqlite", "postgresql"])
    parser.add_argument("--requests", type=int, default=200)
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="trikecert-calls-"))
    url = fresh_database(args.backend, scratch)
    env = dict(os.environ, TRIKECERT_DATABASE_URL=url, TRIKECERT_ENVIRONMENT="test")
    env["TRIKECERT_STATION_RATE_LIMIT"] = "1000000000"
    try:
        key = seed(env)
        os.environ.update(env)
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115  (the access log is written, to nowhere)
        CALLS.install()
        from fastapi.testclient import TestClient

        from app.main import create_app

        with TestClient(create_app()) as client:
            headers = {"Authorization": f"Bearer {key}"}

            def post(n: int) -> None:
                answer = client.post("/api/v1/inspections", json=body(n), headers=headers)
                assert answer.status_code == 201, answer.text

            def post_once(n: int) -> None:
                keyed = {**headers, "Idempotency-Key": f"calls-{time.time_ns()}-{n}"}
                answer = client.post("/api/v1/inspections", json=body(n), headers=keyed)
                assert answer.status_code == 201, answer.text

            def health(_n: int) -> None:
                assert client.get("/healthz").status_code == 200

            rows = [
                ("GET /healthz", count(args.requests, health)),
                ("POST /api/v1/inspections", count(args.requests, post)),
                ("POST + Idempotency-Key", count(args.requests, post_once)),
            ]
        from peer import create_table, peer_app

        os.environ["PEER_DATABASE_URL"] = url
        create_table(url)
        with TestClient(peer_app) as peer:

            def peer_post(n: int) -> None:
                answer = peer.post("/api/v1/inspections", json=body(n))
                assert answer.status_code == 201, answer.text

            rows.append(("peer POST (one row)", count(args.requests, peer_post)))
        print(f"{args.backend}, {args.requests} requests each, in-process (TestClient's own calls included)")
        print("| request | SQL statements | commits | Python calls |")
        print("| --- | --- | --- | --- |")
        for name, figures in rows:
            print(
                f"| {name} | {figures['statements']:.1f} | {figures['commits']:.1f} | "
                f"{figures['calls']:.0f} |"
            )
        print()
        names = sorted(
            {k for _, f in rows for k in f if k.startswith("calls in ")}, key=lambda k: -rows[1][1].get(k, 0)
        )
        print(
            "| Python calls per request, by the package of the calling code | "
            + " | ".join(r[0] for r in rows)
            + " |"
        )
        print("| --- |" + " --- |" * len(rows))
        for name in names:
            cells = " | ".join(f"{f.get(name, 0):.0f}" for _, f in rows)
            print(f"| {name.removeprefix('calls in ')} | {cells} |")
        if BY_STEP:
            print()
            print("| Python calls per POST, by the innermost trikecert line on the stack | calls |")
            print("| --- | --- |")
            for name, n in rows[1][1].items():
                if name.startswith("step "):
                    print(f"| `{name.removeprefix('step ')}` | {n:.0f} |")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
        if args.backend == "postgresql":
            drop_database(url)


if __name__ == "__main__":
    main()
