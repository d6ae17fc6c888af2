"""The trust bundle at scale: time to build it, its bytes (raw and gzip), and the time to serve it
from the kept copy, at 1,000,000 certificates and 50,000 revocations by default.

Run by hand, on a quiet machine only (the numbers are wall-clock):

    .venv/bin/python bench/bundle.py [--certificates 1000000] [--revocations 50000]
                                     [--supersessions 10000] [--repeat 200]

Makes a fresh SQLite database in a temporary folder with the tables (no triggers: the rows are
bulk-loaded with executemany, as no service would write them), one signing key in a key file there,
and the certificates numbered 2026000001... signed (nominally) by that key; revokes the first
`--revocations` certificates after the supersessions. Then times `build_bundle` (gathering the records
and signing), `served_bundle` while nothing changed (what a request costs once the bundle is kept:
the count that proves nothing changed, and a dictionary look-up), and a conditional GET through the
app in-process (304). Prints one line per figure. Small runs (`--certificates 2000`) check the script.
"""

from __future__ import annotations

import argparse
import gzip
import os
import statistics
import sys
import tempfile
import time
from datetime import UTC, datetime, timedelta
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def _load(url: str, certificates: int, revocations: int, supersessions: int) -> None:
    """The tables, one key, and the rows (executemany in batches)."""
    from sqlalchemy import create_engine, insert

    import app.models  # noqa: F401  (every table)
    from app.certificates.models import Certificate, CertificateRevocation, CertificateSequence
    from app.config import get_settings
    from app.db import Base
    from app.db import get_sessionmaker as sessions
    from app.trust.keys import current_signer

    engine = create_engine(url)
    Base.metadata.create_all(engine)
    with sessions()() as session:
        signer = current_signer(session, get_settings())
        session.commit()
    start = datetime(2026, 1, 1, tzinfo=UTC)
    batch = 20_000
    with engine.begin() as connection:
        connection.exec_driver_sql("PRAGMA foreign_keys = OFF")
        for first in range(1, certificates + 1, batch):
            rows = []
            for n in range(first, min(first + batch, certificates + 1)):
                issued = start + timedelta(seconds=n * 20)
                rows.append(
                    {
                        "id": n,
                        "number": f"TRK-2026-{n:06d}-A",
                        "year": 2026 if n < 1_000_000 else 2027,
                        "sequence": n if n < 1_000_000 else n - 999_999,
                        "kind": "compliant",
                        "inspection_id": n,
                        "vehicle_id": n,
                        "registration_number": f"BEN {n:07d}",
                        "compliant": True,
                        "max_compliant_occupants": 3,
                        "issued_at": issued,
                        "expires_at": issued + timedelta(days=365),
                        "issued_by": "station:1",
                        "supersedes_id": n - supersessions if n > certificates - supersessions else None,
                        "facts": {},
                        "key_id": signer.kid,
                        "qr_payload": "",
                        "pdf": b"",
                        "pdf_sha256": "0" * 64,
                    }
                )
            connection.execute(insert(Certificate), rows)
        revoked_at = start + timedelta(days=200)
        connection.execute(
            insert(CertificateRevocation),
            [
                {"certificate_id": n, "revoked_at": revoked_at, "revoked_by": "cli:bench", "reason": "bench"}
                for n in range(1, revocations + 1)
            ],
        )
        connection.execute(
            insert(CertificateSequence), [{"year": 2026, "last_value": min(certificates, 999_999)}]
        )


def _timed(action: object, repeat: int) -> list[float]:
    times = []
    for _ in range(repeat):
        began = time.perf_counter()
        action()  # type: ignore[operator]
        times.append(time.perf_counter() - began)
    return times


def main() -> int:
    """Build, measure, print."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--certificates", type=int, default=1_000_000)
    parser.add_argument("--revocations", type=int, default=50_000)
    parser.add_argument("--supersessions", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=200)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="trikecert-bundle-bench-"))
    url = f"sqlite:///{folder / 'bench.db'}"
    os.environ.update(
        TRIKECERT_DATABASE_URL=url,
        TRIKECERT_SIGNING_KEY_FILE=str(folder / "key.pem"),
        TRIKECERT_ENVIRONMENT="test",
        TRIKECERT_PUBLIC_RATE_LIMIT="0",  # the conditional GETs below are not a flood
    )
    began = time.perf_counter()
    _load(url, args.certificates, args.revocations, args.supersessions)
    print(
        f"rows loaded: {args.certificates} certificates, {args.revocations} revocations, "
        f"{args.supersessions} supersessions in {time.perf_counter() - began:.1f} s"
    )

    from fastapi.testclient import TestClient

    from app.certificates.trust_bundle import build_bundle, forget_bundles, served_bundle
    from app.config import get_settings
    from app.db import get_sessionmaker
    from app.main import create_app

    settings = get_settings()
    with get_sessionmaker()() as session:
        builds = _timed(lambda: build_bundle(session, settings), 3)
        built = build_bundle(session, settings)
        forget_bundles()
        served_bundle(session, settings)
        kept = _timed(lambda: served_bundle(session, settings), args.repeat)
    print(f"build: median {statistics.median(builds):.2f} s of 3 (gather the records, sign, gzip)")
    print(
        f"bytes: {len(built.body):,} raw, {len(built.gzipped):,} gzip "
        f"(level 6; {len(gzip.compress(built.body, 9)):,} at level 9)"
    )
    print(
        f"served from the kept copy: median {statistics.median(kept) * 1000:.2f} ms "
        f"(p90 {sorted(kept)[int(len(kept) * 0.9)] * 1000:.2f} ms) over {args.repeat}"
    )
    with TestClient(create_app()) as client:
        first = client.get("/.well-known/trikecert-trust", headers={"Accept-Encoding": "gzip"})
        etag = first.headers["etag"]
        headers = {"Accept-Encoding": "gzip", "If-None-Match": etag}
        conditional = _timed(lambda: client.get("/.well-known/trikecert-trust", headers=headers), args.repeat)
        assert client.get("/.well-known/trikecert-trust", headers=headers).status_code == 304
    print(
        f"conditional GET (304, in-process TestClient): median {statistics.median(conditional) * 1000:.2f} ms"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
