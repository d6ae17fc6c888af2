"""One kept answer's cost in-process: the bundle's conditional GET through the whole app, no HTTP.

Run by hand:  .venv/bin/python bench/door.py [--requests 20000] [--profile] 2> /dev/null

Makes a fresh SQLite database in a temporary folder (removed at the end), takes the bundle once (so
it is kept), then calls the app's ASGI callable with `If-None-Match` in a loop and prints the
microseconds per request; with --profile, cProfile's 30 most costly functions by their own time. The
access log is formatted and written to standard error, as when served: send it away.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, TextIO

# bench/profile.py would shadow the standard library's `profile`, which cProfile imports.
sys.path[:] = [entry for entry in sys.path if Path(entry or ".").resolve() != Path(__file__).resolve().parent]
import cProfile  # noqa: E402
import pstats  # noqa: E402

BUNDLE = b"/.well-known/trikecert-trust"


def scope_of(headers: list[tuple[bytes, bytes]]) -> dict[str, Any]:
    """A plain GET of the bundle from one client, as uvicorn hands it to the app."""
    return {
        "type": "http",
        "asgi": {"version": "3.0"},
        "http_version": "1.1",
        "method": "GET",
        "scheme": "http",
        "path": BUNDLE.decode(),
        "raw_path": BUNDLE,
        "query_string": b"",
        "root_path": "",
        "headers": headers,
        "client": ("127.0.0.1", 5000),
        "server": ("127.0.0.1", 8000),
        "state": {},
    }


async def call(app: Any, headers: list[tuple[bytes, bytes]]) -> list[dict[str, Any]]:
    """The messages the app sends for one request."""
    sent: list[dict[str, Any]] = []

    async def receive() -> dict[str, Any]:
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(message: dict[str, Any]) -> None:
        sent.append(message)

    await app(scope_of(headers), receive, send)
    return sent


async def measure(app: Any, requests: int, profile: bool, out: TextIO) -> None:
    """Print the 304's cost per request (and its profile) on `out`."""
    first = await call(app, [(b"host", b"bench")])
    etag = dict(first[0]["headers"])[b"etag"]
    conditional = [(b"host", b"bench"), (b"if-none-match", etag)]
    assert (await call(app, conditional))[0]["status"] == 304
    for _ in range(2000):  # warm: the kept answer, the pools, the caches
        await call(app, conditional)
    started = time.perf_counter()
    for _ in range(requests):
        await call(app, conditional)
    print(f"304 in-process: {(time.perf_counter() - started) / requests * 1e6:.1f} us per request", file=out)
    if profile:
        profiler = cProfile.Profile()
        profiler.enable()
        for _ in range(5000):
            await call(app, conditional)
        profiler.disable()
        pstats.Stats(profiler, stream=out).sort_stats("tottime").print_stats(30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=20000)
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="trikecert-door-") as folder:
        os.environ["TRIKECERT_DATABASE_URL"] = f"sqlite:///{folder}/door.db"
        os.environ["TRIKECERT_SIGNING_KEY_FILE"] = f"{folder}/signing-key.pem"
        os.environ["TRIKECERT_PUBLIC_RATE_LIMIT"] = "1000000000"
        from app.db import get_engine
        from app.main import create_app
        from app.migrate import upgrade

        upgrade(get_engine())
        asyncio.run(measure(create_app(), args.requests, args.profile, sys.stdout))
        get_engine().dispose()


if __name__ == "__main__":
    main()
