"""/metrics in Prometheus text format: request metrics plus inspections and certificates by verdict."""

from __future__ import annotations

import os
from collections.abc import Iterable
from typing import Any

from fastapi import APIRouter, Response
from prometheus_client import CONTENT_TYPE_LATEST, CollectorRegistry, generate_latest, multiprocess
from prometheus_client.core import GaugeMetricFamily, Metric
from prometheus_client.registry import REGISTRY, Collector
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from app.certificates.models import Certificate
from app.db import get_sessionmaker
from app.inspections.models import Inspection

router = APIRouter(tags=["operations"])


class StoredCounts(Collector):
    """Counts read from the database at scrape time, so every worker reports the same figures."""

    def collect(self) -> list[Metric]:
        """Inspections and certificates by verdict."""
        with get_sessionmaker()() as session:
            return [
                _by_verdict(session, Inspection.compliant, "trikecert_inspections", "Stored inspections"),
                _by_verdict(session, Certificate.compliant, "trikecert_certificates", "Issued certificates"),
            ]


def _by_verdict(session: Session, column: Any, name: str, what: str) -> Metric:
    """A gauge of how many rows carry each overall verdict."""
    rows = session.execute(select(column, func.count()).group_by(column)).all()
    counts = {bool(compliant): int(count) for compliant, count in rows}
    gauge = GaugeMetricFamily(name, f"{what} by overall verdict", labels=["verdict"])
    gauge.add_metric(["compliant"], counts.get(True, 0))
    gauge.add_metric(["non_compliant"], counts.get(False, 0))
    return gauge


class ProcessMetrics(Collector):
    """This process's own metrics (the default registry), for a single-process server."""

    def collect(self) -> Iterable[Metric]:
        """Everything in the default registry."""
        return REGISTRY.collect()


def registry() -> CollectorRegistry:
    """A registry for one scrape: request metrics (merged across workers when
    PROMETHEUS_MULTIPROC_DIR is set) and the stored counts."""
    scrape = CollectorRegistry()
    if os.environ.get("PROMETHEUS_MULTIPROC_DIR"):
        multiprocess.MultiProcessCollector(scrape)  # type: ignore[no-untyped-call]
    else:
        scrape.register(ProcessMetrics())
    scrape.register(StoredCounts())
    return scrape


@router.get("/metrics", include_in_schema=False)
def metrics() -> Response:
    """Request counts and latencies, and the stored inspections by verdict."""
    return Response(generate_latest(registry()), media_type=CONTENT_TYPE_LATEST)
