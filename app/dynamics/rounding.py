"""The estimates rounded as the API shows them (the inspection's answer and the dynamics endpoint)."""

from __future__ import annotations

from app.stability.dynamics import CaseDynamics


def rounded(value: float | None, places: int) -> float | None:
    """An estimate rounded for display; None (unknown) stays None."""
    return None if value is None else round(value, places)


def case_figures(figures: CaseDynamics) -> dict[str, float | None]:
    """One case's estimates rounded as shown: heights 0.1 mm, thresholds 0.0001 g, speeds 0.1 km/h."""
    return {
        "cg_height_m": rounded(figures.cg_height_m, 4),
        "rollover_threshold_g": rounded(figures.rollover_threshold_g, 4),
        "tilt_angle_deg": rounded(figures.tilt_angle_deg, 2),
        "understeer_margin_nm_per_rad": rounded(figures.understeer_margin_nm_per_rad, 1),
        "critical_speed_kmh": rounded(figures.critical_speed_kmh, 1),
    }
