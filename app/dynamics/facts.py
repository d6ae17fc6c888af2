"""The estimates beyond the static test as a certificate freezes them at issue (shown, never certified)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from app.config import get_settings
from app.dynamics.presentation import estimates
from app.dynamics.protocols import EstimatedInspection
from app.i18n.active import use_locale
from app.i18n.locales import ENGLISH
from app.web.chart import MapPoint, short_label


@dataclass(frozen=True)
class CaseEstimateFacts:
    """One loading case's estimates, in words as printed, and its place on the stability map."""

    label: str
    short_label: str
    lsf: float
    compliant: bool
    cg_height: str
    rollover_threshold: str
    tilt_angle: str
    critical_speed: str
    rollover_g: float | None


@dataclass(frozen=True)
class EstimateFacts:
    """The section of the document beyond the static test: per case, the inputs used, what is missing."""

    cases: tuple[CaseEstimateFacts, ...]
    inputs: tuple[tuple[str, str], ...]
    missing: str | None
    min_rollover_g: float | None

    @property
    def map_points(self) -> list[MapPoint]:
        """The cases whose rollover threshold is known, as points of the stability map."""
        return [
            MapPoint(c.short_label, c.label, c.lsf, c.rollover_g, c.compliant)
            for c in self.cases
            if c.rollover_g is not None
        ]


def estimate_facts(inspection: EstimatedInspection) -> EstimateFacts | None:
    """The inspection's estimates to freeze (in English, the binding text), or None when none is known."""
    with use_locale(ENGLISH):
        content = estimates(inspection)
    if not content.known:
        return None
    thresholds = {p.long_label: p.rollover_g for p in content.points}
    return EstimateFacts(
        cases=tuple(
            CaseEstimateFacts(
                label=row.label,
                short_label=short_label(row.occupants),
                lsf=row.lsf,
                compliant=row.compliant,
                cg_height=row.cg_height,
                rollover_threshold=row.rollover_threshold,
                tilt_angle=row.tilt_angle,
                critical_speed=row.critical_speed,
                rollover_g=thresholds.get(row.label),
            )
            for row in content.rows
        ),
        inputs=tuple(content.inputs),
        missing=content.missing,
        min_rollover_g=get_settings().min_rollover_g,
    )


def estimates_from_json(data: dict[str, Any] | None) -> EstimateFacts | None:
    """The frozen estimates back from a snapshot (None in snapshots without them)."""
    if not data:
        return None
    return EstimateFacts(
        cases=tuple(CaseEstimateFacts(**case) for case in data["cases"]),
        inputs=tuple((label, value) for label, value in data["inputs"]),
        missing=data.get("missing"),
        min_rollover_g=data.get("min_rollover_g"),
    )
