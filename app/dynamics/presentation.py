"""What the inspection page and the PDF show beyond the static test: figures, their inputs, the map."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from markupsafe import Markup

from app.config import get_settings
from app.dynamics.estimates import inspection_dynamics
from app.dynamics.protocols import EstimatedInspection
from app.dynamics.wording import (
    NONE_ON_FILE,
    NOT_RECORDED,
    REVISION,
    critical_speed_text,
    figure_text,
    map_caption,
    missing_sentence,
    not_known,
    readings_text,
    section_lead,
    section_title,
)
from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.stability import DELTA, Layout, layout_named
from app.stability.dynamics import Dynamics, DynamicsInput
from app.web.chart import MapPoint, short_label, stability_map
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
    layout: Layout = DELTA  # the map's limit line and words

    @property
    def known(self) -> bool:
        """Whether any figure at all is known (otherwise the section only says what is missing)."""
        unknown = not_known()
        return any(row.rollover_threshold != unknown or row.understeer_margin != unknown for row in self.rows)


def estimates(inspection: EstimatedInspection) -> Estimates:
    """The estimates of a stored inspection, in words and as map points."""
    data, dynamics = inspection_dynamics(inspection)
    layout = layout_named(inspection.layout)
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
        missing=missing_sentence(dynamics.missing, layout),
        points=points,
        min_rollover_g=get_settings().min_rollover_g,
        layout=layout,
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
        return gap if value is None else figure_text(value, places, unit)

    gap = _(NOT_RECORDED)
    heights = ", ".join(given(z, 2) for z in vehicle.seat_heights_m) or gap
    two_front, one_rear = data.n_front > 1, data.n_rear == 1
    front_tyre = (
        N_("Each front tyre's cornering stiffness") if two_front else N_("Front tyre cornering stiffness")
    )
    rear_tyre = (
        N_("Rear tyre cornering stiffness") if one_rear else N_("Each rear tyre's cornering stiffness")
    )
    rows = [
        (
            N_("Vehicle figures"),
            _(REVISION) % {"revision": revision.revision} if revision else _(NONE_ON_FILE),
        ),
        # One rear wheel has no rear track: the vehicle tips about its front track alone.
        *([] if one_rear else [(N_("Rear track"), given(vehicle.track_m, 3, "m"))]),
        *([(N_("Front track"), given(vehicle.front_track_m, 3, "m"))] if two_front else []),
        (N_("Loaded rear wheel radius"), given(vehicle.wheel_radius_m, 3, "m")),
        (N_("Seated heights, driver first"), heights if heights == gap else f"{heights} m"),
        (front_tyre, given(vehicle.front_cornering_stiffness_n_per_rad, 0, "N/rad")),
        (rear_tyre, given(vehicle.rear_cornering_stiffness_n_per_rad, 0, "N/rad")),
    ]
    if lift is not None:
        raised = N_("Front axle raised by") if two_front else N_("Front wheel raised by")
        reaction = N_("Front axle reaction, raised") if two_front else N_("Front wheel reaction, raised")
        rows.append((raised, figure_text(lift.lift_height_m, 3, "m")))
        rows.append((reaction, readings_text(stored.get("front_kg", []), lift.front_kg)))
    if data.cg_height_m is not None:
        rows.append((N_("Centre of gravity height (given)"), figure_text(data.cg_height_m, 3, "m")))
    rows.append(
        (N_("Empty vehicle's centre of gravity height"), figure_text(dynamics.empty_cg_height_m, 4, "m"))
    )
    return [(_(label), value) for label, value in rows]


def map_svg(content: Estimates, *, chart_id: str = "stability-map") -> Markup | None:
    """The stability map, or None when no case's rollover threshold is known."""
    if not content.points:
        return None
    return stability_map(
        content.points,
        min_rollover_g=content.min_rollover_g,
        chart_id=chart_id,
        limit=content.layout.limit,
        rear_axle_words=content.layout.rear_axle_words,
    )


def dynamics_context(inspection: EstimatedInspection) -> dict[str, object]:
    """The template's `estimates`, `stability_map` and the section's title and lead."""
    content = estimates(inspection)
    return {
        "estimates": content,
        "stability_map": map_svg(content),
        "map_caption": map_caption(content.layout, with_minimum=content.min_rollover_g is not None),
        "estimates_title": section_title(),
        "estimates_lead": section_lead(),
    }
