"""Scale benchmark: N inspections (default 1,000,000) in a fresh PostgreSQL database, then query times.

Run by hand (needs a local PostgreSQL):  .venv/bin/python bench/scale.py
Options: --inspections 1000000 --vehicles 50000 --stations 40 --days 730 --runs 200 --keep

Loads with set-based INSERT ... SELECT generate_series (one statement per table and batch, inside the
server), then times, through the application's own code (app.inspections.service.list_inspections,
the query behind GET /api/v1/inspections and the vehicle page), p50 / p99 over --runs runs each:
a vehicle's history, the filtered list (compliant=false, since, page 1 and a deep page) with its
count, and the statistics page's counts (app.statistics.service.statistics: per local day, per
station, certificates) over the last 30 and 366 days.
"""

from __future__ import annotations

import argparse
import os
import platform
import random
import statistics
import sys
import time
from collections.abc import Callable
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any
from zoneinfo import ZoneInfo

from sqlalchemy import Engine, create_engine, text
from sqlalchemy.engine import make_url
from sqlalchemy.orm import Session

sys.path.insert(0, str(Path(__file__).resolve().parent))
from load import drop_database, new_postgres_database

BATCH = 100_000  # inspections per INSERT ... SELECT (each with 5 loading cases and 12 readings)


LOADED_TABLES = ("inspection", "loading_case", "reading")


def _set_aside(db: Any) -> list[str]:
    """Drop the loaded tables' secondary indexes and foreign keys; the statements that make them again.

    Maintaining four indexes in random order and two foreign-key checks per row made each batch cost
    several times what the rows themselves do; built once at the end, they cost one sort each.
    """
    again: list[str] = []
    for table in LOADED_TABLES:
        for name, definition in db.execute(
            text(
                "SELECT conname, pg_get_constraintdef(oid) FROM pg_constraint "
                "WHERE conrelid = CAST(:t AS regclass) AND contype = 'f'"
            ),
            {"t": table},
        ):
            db.execute(text(f'ALTER TABLE {table} DROP CONSTRAINT "{name}"'))
            again.append(f'ALTER TABLE {table} ADD CONSTRAINT "{name}" {definition}')
        for name, definition in db.execute(
            text(
                "SELECT i.indexname, i.indexdef FROM pg_indexes i WHERE i.tablename = :t AND NOT EXISTS "
                "(SELECT 1 FROM pg_constraint c WHERE c.conname = i.indexname)"
            ),
            {"t": table},
        ):
            db.execute(text(f'DROP INDEX "{name}"'))
            again.append(definition)
    return again


def load(
    engine: Engine, *, inspections: int, vehicles: int, stations: int, days: int, details: bool = True
) -> float:
    """Fill station, vehicle, seat, inspection and (with `details`) loading_case and reading; seconds."""
    started = time.perf_counter()
    now = datetime.now(UTC)
    with engine.begin() as db:
        db.execute(
            text(
                "INSERT INTO station (name, key_hash, key_prefix, active, created_at) "
                "SELECT 'station ' || s, md5('key' || s) || md5('k' || s), 'tks_' || s, true, :now "
                "FROM generate_series(1, CAST(:n AS integer)) s"
            ),
            {"n": stations, "now": now},
        )
        db.execute(
            text(
                "INSERT INTO vehicle (registration_number, registration_key, make, model, wheelbase_m, "
                "created_at) SELECT 'SCL ' || lpad(v::text, 6, '0'), 'SCL' || lpad(v::text, 6, '0'), "
                "'Bajaj', 'RE', 2.0, :now FROM generate_series(1, CAST(:n AS integer)) v"
            ),
            {"n": vehicles, "now": now},
        )
        db.execute(
            text(
                "INSERT INTO seat (vehicle_id, position, role, x_m) SELECT v, p, "
                "CASE WHEN p = 0 THEN 'driver' ELSE 'passenger' END, CASE WHEN p = 0 THEN 0.9303 "
                "ELSE 1.6303 END FROM generate_series(1, CAST(:n AS integer)) v, generate_series(0, 3) p"
            ),
            {"n": vehicles},
        )
        again = _set_aside(db)
    config = '{"seats": [{"role": "driver", "x_m": "0.9303"}], "load_items": []}'
    for first in range(1, inspections + 1, BATCH):
        last = min(first + BATCH - 1, inspections)
        with engine.begin() as db:
            # Spread: vehicles by a multiplicative hash of the id, stations likewise, times uniformly
            # over `days` days back from now (ids are not in time order, as after a backfill).
            db.execute(
                text(
                    "INSERT INTO inspection (id, vehicle_id, registration_number, station_id, created_at, "
                    "wheelbase_m, occupant_mass_kg, sum_tolerance, rules_version, occupant_config, front_kg, "
                    "left_rear_kg, right_rear_kg, overall_kg, cg_from_front_m, compliant, "
                    "max_compliant_occupants) "
                    "SELECT i, 1 + (i * 7919) % :vehicles, "
                    "'SCL ' || lpad(CAST(1 + (i * 7919) % :vehicles AS text), 6, '0'), "
                    "1 + (i * 104729) % :stations, "
                    ":now - ((i * 2654435761) % (:days * 86400)) * interval '1 second', "
                    "2.0, 72, 0.01, 'v1', CAST(:config AS json), 108, 115, 135, 359, 1.1, "
                    "(i % 10) <> 0, CASE WHEN (i % 10) <> 0 THEN 3 ELSE 2 END "
                    "FROM generate_series(CAST(:first AS bigint), "
                    "CAST(:last AS bigint)) i"
                ),
                {
                    "vehicles": vehicles,
                    "stations": stations,
                    "days": days,
                    "now": now,
                    "config": config,
                    "first": first,
                    "last": last,
                },
            )
            if not details:
                continue
            db.execute(
                text(
                    "INSERT INTO loading_case (inspection_id, occupants, total_kg, rear_kg, lsf, variance, "
                    "compliant, measured, lsf_exact) SELECT i, o, 358 + 72 * o, 250 + 50 * o, 0.65, "
                    "0.016666, (i % 10) <> 0 OR o < 3, false, '13/20' "
                    "FROM generate_series(CAST(:first AS bigint), "
                    "CAST(:last AS bigint)) i, generate_series(0, 4) o"
                ),
                {"first": first, "last": last},
            )
            db.execute(
                text(
                    "INSERT INTO reading (inspection_id, case_occupants, wheel, sequence, value_kg) "
                    "SELECT i, 0, w, s, 100 + s FROM generate_series(CAST(:first AS bigint), "
                    "CAST(:last AS bigint)) i, "
                    "unnest(ARRAY['front_kg', 'left_rear_kg', 'right_rear_kg', 'overall_kg']) w, "
                    "generate_series(0, 2) s"
                ),
                {"first": first, "last": last},
            )
        print(f"  loaded {last:,} inspections in {time.perf_counter() - started:.0f} s", flush=True)
    with engine.begin() as db:
        db.execute(text("SET maintenance_work_mem = '512MB'"))
        for statement in again:
            db.execute(text(statement))
        print(f"  indexes and foreign keys made again in {time.perf_counter() - started:.0f} s", flush=True)
        db.execute(text("SELECT setval(pg_get_serial_sequence('inspection', 'id'), :n)"), {"n": inspections})
    with engine.connect().execution_options(isolation_level="AUTOCOMMIT") as db:
        db.execute(text("VACUUM ANALYZE"))
    return time.perf_counter() - started


def timed(runs: int, query: Callable[[int], object]) -> tuple[float, float]:
    """p50 and p99 in milliseconds of `runs` calls of query(run)."""
    times = []
    for run in range(runs):
        started = time.perf_counter()
        query(run)
        times.append((time.perf_counter() - started) * 1000)
    times.sort()
    return statistics.median(times), times[min(len(times) - 1, int(len(times) * 0.99))]


def measure(engine: Engine, *, vehicles: int, runs: int) -> list[tuple[str, float, float]]:
    """Time each query; (name, p50 ms, p99 ms)."""
    from app.db import Base
    from app.inspections.service import InspectionFilter, list_inspections
    from app.statistics.service import Period
    from app.statistics.service import statistics as period_statistics

    rng = random.Random(6)
    since = datetime.now(UTC) - timedelta(days=90)
    with Session(engine) as session:

        def history(_run: int) -> None:
            registration = f"SCL {rng.randint(1, vehicles):06d}"
            where = InspectionFilter(registration_number=registration)
            list_inspections(session, where=where, limit=50, offset=0)
            session.rollback()

        def filtered(offset: int) -> Callable[[int], object]:
            def run(_run: int) -> None:
                list_inspections(
                    session, where=InspectionFilter(compliant=False, since=since), limit=50, offset=offset
                )
                session.rollback()

            return run

        zone = ZoneInfo("Africa/Lagos")
        today = datetime.now(zone).date()

        def daily(days: int, in_zone: ZoneInfo = zone) -> Callable[[int], object]:
            def run(_run: int) -> None:
                period = Period(today - timedelta(days=days - 1), today)
                period_statistics(session, period=period, zone=in_zone)
                session.rollback()

            return run

        history(0)  # warm the caches
        # The closed days' counts are taken from the records once, on the first visit (or by
        # `trikecert count-statistics`); every later visit reads them and counts today live.
        firsts = [
            ("statistics page's counts: first visit, 366 days counted and stored (once)", daily(366)),
            (
                "the same after a change of zone (Asia/Kolkata, UTC+5:30): its days counted once",
                daily(366, ZoneInfo("Asia/Kolkata")),
            ),
        ]
        once = [(name, *timed(1, query)) for name, query in firsts]
        # What autovacuum does within a minute of the first visit's 30,000 new rows: their statistics
        # for the planner, and the visibility map that lets the sums be read from the index alone
        # (every stored count: days, months and the open days' hours).
        stored_counts = [name for name in Base.metadata.tables if name.startswith("statistics_")]
        with engine.connect().execution_options(isolation_level="AUTOCOMMIT") as db:
            db.execute(text(f"VACUUM ANALYZE {', '.join(stored_counts)}"))
        queries = [
            ("vehicle history (registration_number=, newest 50, with count)", history),
            ("filtered list: compliant=false, since 90 days, page 1 + count", filtered(0)),
            ("filtered list: compliant=false, since 90 days, offset 5000 + count", filtered(5000)),
            ("statistics page's counts: last 30 days (per day, per station, certificates)", daily(30)),
            ("statistics page's counts: last 366 days", daily(366)),
        ]
        return once + [(name, *timed(runs, query)) for name, query in queries]


def main() -> None:
    """Load, measure, print a markdown table; drop the database unless --keep."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--inspections", type=int, default=1_000_000)
    parser.add_argument("--vehicles", type=int, default=50_000)
    parser.add_argument("--stations", type=int, default=40)
    parser.add_argument("--days", type=int, default=730)
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--url", help="an already loaded database: skip the load")
    parser.add_argument("--keep", action="store_true", help="keep the database (its URL is printed)")
    parser.add_argument(
        "--no-details",
        dest="details",
        action="store_false",
        help="load no readings or loading cases (no query timed here reads them; 12 + 5 rows each)",
    )
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    url = args.url or new_postgres_database("trikecert_scale")
    os.environ["TRIKECERT_DATABASE_URL"] = url
    engine = create_engine(url)
    try:
        if not args.url:
            from app.migrate import upgrade

            upgrade(engine)
            sizes = {"inspections": args.inspections, "vehicles": args.vehicles, "stations": args.stations}
            seconds = load(engine, **sizes, days=args.days, details=args.details)
            details = (
                f"{5 * args.inspections:,} loading cases, {12 * args.inspections:,} readings"
                if args.details
                else "no readings or loading cases"
            )
            print(
                f"loaded {args.inspections:,} inspections ({details}) over {args.vehicles:,} vehicles "
                f"and {args.stations} stations in {seconds:.0f} s"
            )
        with engine.connect() as db:
            size = db.scalar(text("SELECT pg_size_pretty(pg_database_size(current_database()))"))
        print(f"database size: {size}; url: {make_url(url).render_as_string(hide_password=True)}")
        print(f"| query ({args.runs} runs; the first visits once) | p50 | p99 |")
        print("| --- | --- | --- |")
        for name, p50, p99 in measure(engine, vehicles=args.vehicles, runs=args.runs):
            print(f"| {name} | {p50:.2f} ms | {p99:.2f} ms |", flush=True)
    finally:
        engine.dispose()
        if not args.keep and not args.url:
            drop_database(url)


if __name__ == "__main__":
    main()
