"""Where a submission's time goes: py-spy on one server worker under wrk, summed by library and line.

Run by hand (needs Debian's wrk, py-spy from `pip install -e '.[bench]'`, and for PostgreSQL a local
server):  .venv/bin/python bench/profile.py [--backend postgresql|sqlite] [--seconds 12]

Starts `trikecert serve --workers 1` on a fresh database, loads it with `wrk -c8` and the load
benchmark's POST script, and samples the worker with `py-spy record --gil` (only the thread holding
the GIL, so the shares are of the CPU the process really used). Prints two tables: the share of
samples by the library whose code was running, and by the innermost line of trikecert's own code.
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from load import ROOT, VEHICLES, drop_database, free_port, fresh_database, seed, wait_ready

WEB_STACK = {"asyncio", "uvicorn", "starlette", "fastapi", "anyio", "httptools", "uvloop", "h11"}


def library(frame: str) -> str:
    """The package a py-spy frame ('func (path/file.py:line)') belongs to."""
    found = re.search(r"\(([A-Za-z_0-9]+)/", frame)
    name = found.group(1) if found else "standard library and other"
    if name in WEB_STACK:
        return "web stack (uvicorn, starlette, fastapi, anyio, asyncio)"
    return "trikecert (app/)" if name == "app" else name


def summarise(raw: Path, top: int) -> str:
    """Markdown tables of a py-spy raw profile: by library (innermost frame), by app line."""
    by_library: collections.Counter[str] = collections.Counter()
    by_line: collections.Counter[str] = collections.Counter()
    total = 0
    for line in raw.read_text().splitlines():
        stack, _, count = line.rpartition(" ")
        if not stack:
            continue
        frames, samples = stack.split(";"), int(count)
        total += samples
        by_library[library(frames[-1])] += samples
        own = [f for f in frames if "(app/" in f]
        if own:
            by_line[own[-1]] += samples
    rows = ["| library (innermost frame) | share of samples |", "| --- | --- |"]
    rows += [f"| {name} | {100 * n / total:.1f} % |" for name, n in by_library.most_common()]
    rows += ["", "| innermost trikecert line on the stack | share of samples |", "| --- | --- |"]
    rows += [f"| `{name}` | {100 * n / total:.1f} % |" for name, n in by_line.most_common(top)]
    return "\n".join([f"{total} samples", "", *rows])


def main() -> None:
    """Serve, load, sample, summarise."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--backend", default="postgresql", choices=["postgresql", "sqlite"])
    parser.add_argument("--seconds", type=int, default=12)
    parser.add_argument("--top", type=int, default=15)
    parser.add_argument("--raw", type=Path, help="also keep py-spy's raw profile here (for flame graphs)")
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="trikecert-profile-"))
    env = dict(
        os.environ,
        TRIKECERT_DATABASE_URL=fresh_database(args.backend, scratch),
        TRIKECERT_ENVIRONMENT="test",
        TRIKECERT_STATION_RATE_LIMIT="1000000000",
    )
    key = seed(env)
    port = free_port()
    bin_dir = Path(sys.executable).parent
    server = subprocess.Popen(
        [str(bin_dir / "trikecert"), "serve", "--port", str(port), "--workers", "1", "--no-migrate"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    raw = scratch / "profile.raw"
    try:
        wait_ready(port)
        wrk_env = dict(env, TRIKECERT_BENCH_KEY=key, TRIKECERT_BENCH_VEHICLES=str(VEHICLES))
        script = str(ROOT / "bench/post_inspection.lua")
        wrk = ["wrk", "-t1", "-c8", "-s", script, f"http://127.0.0.1:{port}"]
        subprocess.run([*wrk[:2], "-d3s", *wrk[2:]], env=wrk_env, capture_output=True, check=True)  # warm up
        sampling = ["--gil", "-r", "100", "-d", str(args.seconds), "-f", "raw", "-o", str(raw)]
        spy = subprocess.Popen(
            [str(bin_dir / "py-spy"), "record", *sampling, "-p", str(server.pid), "--nonblocking"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        load = subprocess.run(
            [*wrk[:2], f"-d{args.seconds}s", "--latency", *wrk[2:]],
            env=wrk_env,
            capture_output=True,
            text=True,
            check=True,
        )
        spy.wait(timeout=args.seconds + 30)
        rate = re.search(r"Requests/sec:\s+([\d.]+)", load.stdout)
        print(f"{args.backend}, 1 worker, wrk -c8: {rate.group(1) if rate else '?'} POST/s while sampled")
        print(summarise(raw, args.top))
        if args.raw:
            shutil.copy(raw, args.raw)
    finally:
        server.terminate()
        server.wait(timeout=30)
        shutil.rmtree(scratch, ignore_errors=True)
        if args.backend == "postgresql":
            drop_database(env["TRIKECERT_DATABASE_URL"])


if __name__ == "__main__":
    main()
