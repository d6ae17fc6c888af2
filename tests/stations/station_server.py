"""A real `trikecert serve` process on the test database, for the tests that need separate workers
or a service that goes away: start it, stop it, kill it (with its workers), start it again."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

from served import free_port, wait_until_ready
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.inspections.models import Inspection
from app.stations.service import create_station
from app.vehicles.service import register_vehicle

STUDY_SEATS = [("driver", "0.9303")] + [("passenger", "1.6303")] * 3


class Server:
    """`python -m app.cli serve` in its own process group, so its workers go with it."""

    def __init__(self, database_url: str, *, workers: int = 1, env: dict[str, str] | None = None) -> None:
        self.port = free_port()
        self.workers = workers
        self.env = dict(os.environ, TRIKECERT_DATABASE_URL=database_url, **(env or {}))
        self.process: subprocess.Popen[bytes] | None = None

    @property
    def url(self) -> str:
        """The base address, such as http://127.0.0.1:41234."""
        return f"http://127.0.0.1:{self.port}"

    def start(self, *, timeout: float = 30.0) -> None:
        """Start serving (the database is already migrated) and wait until /readyz answers."""
        command = [sys.executable, "-m", "app.cli", "serve", "--port", str(self.port), "--no-migrate"]
        self.process = subprocess.Popen(
            [*command, "--workers", str(self.workers)],
            env=self.env,
            cwd=Path(__file__).resolve().parents[2],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        try:
            wait_until_ready(f"{self.url}/readyz", self.process, timeout=timeout)
        except AssertionError:
            self.kill()
            raise

    def _signal(self, number: int) -> None:
        if self.process is None:
            return
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.process.pid, number)
        self.process.wait(timeout=30)
        self.process = None

    def stop(self) -> None:
        """Shut down gracefully (SIGTERM to the whole group)."""
        self._signal(signal.SIGTERM)

    def kill(self) -> None:
        """Die at once, as in a crash or a power cut (SIGKILL to the whole group)."""
        self._signal(signal.SIGKILL)


def seed_station(session: Session, name: str) -> tuple[int, str]:
    """A new station: its id and key."""
    station, key = create_station(session, name=name)
    return station.id, key


def seed_study_vehicle(session: Session, registration_number: str = "BDG 252 QH") -> None:
    """The study's tricycle, registered."""
    register_vehicle(
        session,
        registration_number=registration_number,
        make="Bajaj",
        model="RE",
        wheelbase_m=Decimal("2.000"),
        seats=[(role, Decimal(x)) for role, x in STUDY_SEATS],
    )


def count_inspections(session: Session) -> int:
    """How many inspections the database holds (read afresh)."""
    session.expire_all()
    return int(session.scalar(select(func.count()).select_from(Inspection)) or 0)
