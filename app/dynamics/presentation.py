"""What the inspection page and the PDF show beyond the static test: figures, their inputs, the map."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from markupsafe import Markup

from app.config import get_settings
from app.dynamics.estimates import inspection_dynamics
from app.dynamics.protocols import EstimatedInspection
from app.dynamics.wording import (
    SECTION_LEAD,
    SECTION_TITLE,
    UNKNOWN,
    critical_speed_text,
    figure_text,
    missing_sentence,
    readings_text,
)
from app.stability.dynamics import Dynamics, DynamicsInput
from app.web.chart import MapPoint, short_label, stability_map
from app.web.formatting import NOT_RECORDED
from app.wording import case_name


@dataclass(frozen=True)
class EstimateRow:
    """One loading case's estimates in words, for a table row."""

    occupants: int
    label: str
    compliant: bool
    lsf: float
    cg_height: str
    rollover_threshold: str
    tilt_angle: str
    understeer_margin: str
    critical_speed: str


@dataclass(frozen=True)
class Estimates:
    """The section's content: the rows, the inputs used, what is missing and the map's points."""

    rows: list[EstimateRow]
    inputs: list[tuple[str, str]]
    missing: str | None
    points: list[MapPoint]
    min_rollover_g: float | None

    @property
    def known(self) -> bool:
        """Whether any figure at all is known (otherwise the section only says what is missing)."""
        return any(row.rollover_threshold != UNKNOWN or row.understeer_margin != UNKNOWN for row in self.rows)


def estimates(inspection: EstimatedInspection) -> Estimates:
    """The estimates of a stored inspection, in words and as map points."""
    data, dynamics = inspection_dynamics(inspection)
    rows, points = [], []
    for case, figures in zip(inspection.loading_cases, dynamics.cases, strict=True):
        lsf = float(case.lsf)
        rows.append(
            EstimateRow(
                occupants=case.occupants,
                label=case_name(case.occupants),
                compliant=case.compliant,
                lsf=lsf,
                cg_height=figure_text(figures.cg_height_m, 4, "m"),
                rollover_threshold=figure_text(figures.rollover_threshold_g, 4, "g"),
                tilt_angle=figure_text(figures.tilt_angle_deg, 2, "°"),
                understeer_margin=figure_text(figures.understeer_margin_nm_per_rad, 1, "N·m/rad"),
                critical_speed=critical_speed_text(
                    figures.critical_speed_kmh, figures.understeer_margin_nm_per_rad
                ),
            )
        )
        if figures.rollover_threshold_g is not None:
            points.append(
                MapPoint(
                    short_label(case.occupants),
                    case_name(case.occupants),
                    lsf,
                    figures.rollover_threshold_g,
                    case.compliant,
                )
            )
    return Estimates(
        rows=rows,
        inputs=inputs_used(inspection, data, dynamics),
        missing=missing_sentence(dynamics.missing),
        points=points,
        min_rollover_g=get_settings().min_rollover_g,
    )


def inputs_used(
    inspection: EstimatedInspection, data: DynamicsInput, dynamics: Dynamics
) -> list[tuple[str, str]]:
    """The inputs beside the figures, each labelled with its unit; unknown ones say so."""
    vehicle = data.vehicle
    revision = inspection.dynamics_revision
    stored = (inspection.dynamics_input or {}).get("cg_lift") or {}
    lift = data.cg_lift

    def given(value: float | Decimal | None, places: int, unit: str = "") -> str:
        # An input left empty on the vehicle's record, worded as every page words a gap.
        return NOT_RECORDED if value is None else figure_text(value, places, unit)

    heights = ", ".join(given(z, 2) for z in vehicle.seat_heights_m) or NOT_RECORDED
    rows = [
        ("Vehicle figures", f"revision {revision.revision}" if revision else "None on file"),
        ("Rear track", given(vehicle.track_m, 3, "m")),
        *([("Front track", given(vehicle.front_track_m, 3, "m"))] if data.n_front > 1 else []),
        ("Loaded rear wheel radius", given(vehicle.wheel_radius_m, 3, "m")),
        ("Seated heights, driver first", heights if heights == NOT_RECORDED else f"{heights} m"),
        (
            "Front tyre cornering stiffness",
            given(vehicle.front_cornering_stiffness_n_per_rad, 0, "N/rad"),
        ),
        (
            "Each rear tyre's cornering stiffness",
            given(vehicle.rear_cornering_stiffness_n_per_rad, 0, "N/rad"),
        ),
    ]
    if lift is not None:
        rows.append(("Front wheel raised by", figure_text(lift.lift_height_m, 3, "m")))
        rows.append(
            ("Front wheel reaction, raised", readings_text(stored.get("front_kg", []), lift.front_kg))
        )
    if data.cg_height_m is not None:
        rows.append(("Centre of gravity height (given)", figure_text(data.cg_height_m, 3, "m")))
    rows.append(("Empty vehicle's centre of gravity height", figure_text(dynamics.empty_cg_height_m, 4, "m")))
    return rows


def map_svg(content: Estimates, *, chart_id: str = "stability-map") -> Markup | None:
    """The stability map, or None when no case's rollover threshold is known."""
    if not content.points:
        return None
    return stability_map(content.points, min_rollover_g=content.min_rollover_g, chart_id=chart_id)


def dynamics_context(inspection: EstimatedInspection) -> dict[str, object]:
    """The template's `estimates`, `stability_map` and the section's title and lead."""
    content = estimates(inspection)
    return {
        "estimates": content,
        "stability_map": map_svg(content),
        "estimates_title": SECTION_TITLE,
        "estimates_lead": SECTION_LEAD,
    }
