"""PDF benchmark: milliseconds per certificate, first render (new certificate) and repeat download.

Run by hand:  .venv/bin/python bench/pdf.py [--certificates 100] [--downloads 500] [--database URL]

On a fresh database (SQLite in a temporary folder unless --database names an empty PostgreSQL
database), through the application in-process (FastAPI TestClient, no network):
- render: app.certificates.pdf.render_pdf alone, timed inside each issue (the first call, which
  prepares the embedded Noto Sans from the variable font, is reported apart);
- issue: POST /api/v1/inspections/{id}/certificate, a new certificate of a stored inspection
  (number, signature, facts, render, store);
- download: GET /api/v1/certificates/{number}/pdf, the stored bytes again.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any


def summary(name: str, times: list[float]) -> str:
    """A markdown row: count, median, p90, p99 (ms)."""
    ordered = sorted(times)
    p90 = ordered[min(len(ordered) - 1, int(len(ordered) * 0.9))]
    p99 = ordered[min(len(ordered) - 1, int(len(ordered) * 0.99))]
    return f"| {name} | {len(times)} | {statistics.median(times):.2f} | {p90:.2f} | {p99:.2f} |"


def main() -> None:
    """Set up a database, issue certificates, download them, print a markdown table."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--certificates", type=int, default=100)
    parser.add_argument("--downloads", type=int, default=500)
    parser.add_argument("--database", help="an empty database URL (default: SQLite in a temporary folder)")
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="trikecert-pdf-"))
    os.environ["TRIKECERT_DATABASE_URL"] = args.database or f"sqlite:///{scratch / 'pdf.db'}"
    os.environ["TRIKECERT_ENVIRONMENT"] = "test"
    os.environ["TRIKECERT_STATION_RATE_LIMIT"] = "0"

    from decimal import Decimal

    from fastapi.testclient import TestClient

    import app.certificates.service as certificates
    from app.certificates.pdf import render_pdf
    from app.db import get_engine, get_sessionmaker
    from app.main import create_app
    from app.migrate import upgrade
    from app.stations.service import create_station
    from app.vehicles.service import register_vehicle

    upgrade(get_engine())
    with get_sessionmaker()() as session:
        _station, key = create_station(session, name="pdf bench")
        for i in range(args.certificates):
            register_vehicle(
                session,
                registration_number=f"PDF {i:04d}",
                make="Bajaj",
                model="RE",
                wheelbase_m=Decimal("2.000"),
                seats=[("driver", Decimal("0.9303"))] + [("passenger", Decimal("1.6303"))] * 3,
            )

    renders: list[float] = []
    real_render: Callable[..., bytes] = render_pdf

    def timed_render(*a: Any, **kw: Any) -> bytes:
        started = time.perf_counter()
        try:
            return real_render(*a, **kw)
        finally:
            renders.append((time.perf_counter() - started) * 1000)

    setattr(certificates, "render_pdf", timed_render)  # noqa: B010  (time each render inside the issue)
    issues: list[float] = []
    downloads: list[float] = []
    sizes: list[int] = []
    with TestClient(create_app()) as client:
        client.headers["Authorization"] = f"Bearer {key}"
        numbers = []
        for i in range(args.certificates):
            front = 108 if i % 4 else 150  # every fourth one is a refusal (not compliant)
            body = {
                "registration_number": f"PDF {i:04d}",
                "readings": {"front_kg": [front] * 3, "left_rear_kg": [115] * 3, "right_rear_kg": [135] * 3},
            }
            created = client.post("/api/v1/inspections", json=body)
            assert created.status_code == 201, created.text
            started = time.perf_counter()
            issued = client.post(f"/api/v1/inspections/{created.json()['id']}/certificate")
            issues.append((time.perf_counter() - started) * 1000)
            assert issued.status_code == 201, issued.text
            numbers.append(issued.json()["number"])
        for i in range(args.downloads):
            started = time.perf_counter()
            pdf = client.get(f"/api/v1/certificates/{numbers[i % len(numbers)]}/pdf")
            downloads.append((time.perf_counter() - started) * 1000)
            assert pdf.status_code == 200
            assert pdf.content.startswith(b"%PDF")
            sizes.append(len(pdf.content))

    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"{sys.platform}; database: {get_engine().dialect.name}; PDF size median "
        f"{statistics.median(sizes) / 1024:.1f} KiB"
    )
    print("| step | n | median ms | p90 ms | p99 ms |")
    print("| --- | --- | --- | --- | --- |")
    print(f"| render_pdf, first call in the process (fonts prepared) | 1 | {renders[0]:.2f} | | |")
    print(summary("render_pdf, each new certificate after the first", renders[1:]))
    print(summary("POST .../certificate (issue: number, sign, render, store)", issues[1:]))
    print(summary("GET /api/v1/certificates/{number}/pdf (stored bytes)", downloads))


if __name__ == "__main__":
    main()
