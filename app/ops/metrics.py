"""/metrics in Prometheus text format: request metrics plus inspections and certificates by verdict.

With TRIKECERT_METRICS_TOKEN set, a scrape must send `Authorization: Bearer <token>` (401 otherwise).
Without it the endpoint is off (404) in production, and open in development and tests, where there
is nothing to protect and a local Prometheus need not be configured.
"""

from __future__ import annotations

import hmac
import os
from collections.abc import Iterable
from typing import Any

from fastapi import APIRouter, Request, Response
from prometheus_client import CONTENT_TYPE_LATEST, CollectorRegistry, generate_latest, multiprocess
from prometheus_client.core import GaugeMetricFamily, Metric
from prometheus_client.registry import REGISTRY, Collector
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from starlette.exceptions import HTTPException

from app.certificates.models import Certificate
from app.config import get_settings
from app.db import get_sessionmaker
from app.errors import ServiceError
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


class MetricsRefused(ServiceError):
    """A scrape without the metrics token (401)."""

    status = 401
    headers = {"WWW-Authenticate": 'Bearer realm="metrics"'}  # noqa: RUF012


def check_scraper(request: Request) -> None:
    """Let the scrape through, or refuse it as the settings say (404 off, 401 no or wrong token)."""
    settings = get_settings()
    token = settings.metrics_token
    if token is None:
        if settings.environment == "production":
            raise HTTPException(404)  # off: answered as any unknown path is
        return
    given = request.headers.get("authorization", "")
    expected = f"Bearer {token.get_secret_value()}"
    if not hmac.compare_digest(given.encode("utf-8", "replace"), expected.encode()):
        raise MetricsRefused(
            "Authorization: /metrics needs `Authorization: Bearer <TRIKECERT_METRICS_TOKEN>`",
            field="Authorization",
            rule="metrics_token",
        )


@router.get("/metrics", include_in_schema=False)
def metrics(request: Request) -> Response:
    """Request counts and latencies, and the stored inspections by verdict."""
    check_scraper(request)
    return Response(generate_latest(registry()), media_type=CONTENT_TYPE_LATEST)
