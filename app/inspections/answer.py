"""The API's view of an inspection: its stored values, figures rounded for display, verdicts as stored.

The same function answers the submission (from the record just written) and every later read (from
the record read back), so the two can never disagree.
"""

from __future__ import annotations

from decimal import Decimal

from app.dynamics.rounding import case_figures
from app.inspections.record import InspectionRecord
from app.inspections.schemas import InspectionOut
from app.stability import case_label
from app.stability.dynamics import Dynamics


def _f(value: Decimal, places: int) -> float:
    return float(round(value, places))


def _base_readings(record: InspectionRecord) -> dict[str, list[Decimal]]:
    """Each wheel's raw readings of the base weighing (case 0), in their order."""
    values: dict[str, list[Decimal]] = {}
    for reading in record.readings:
        if reading.case_occupants == 0:
            values.setdefault(reading.wheel, []).append(reading.value_kg)
    return values


def inspection_answer(record: InspectionRecord, estimates: Dynamics) -> InspectionOut:
    """The full API view of an inspection and its estimates (validated in one call from plain data)."""
    raw = _base_readings(record)
    calibration = None
    if record.calibration_certificate is not None or record.calibration_valid_until is not None:
        calibration = {
            "certificate": record.calibration_certificate,
            "valid_until": record.calibration_valid_until,
        }
    config = record.occupant_config
    return InspectionOut.model_validate(
        {
            "id": record.id,
            "registration_number": record.registration_number,
            "station": record.station_name,
            "created_at": record.created_at,
            "compliant": record.compliant,
            "max_compliant_occupants": record.max_compliant_occupants,
            "vehicle_id": record.vehicle_id,
            "wheelbase_m": float(record.wheelbase_m),
            "layout": record.layout,
            "readings": {
                **{wheel: _f(value, 3) for wheel, value in record.wheel_means().items()},
                "overall_kg": _f(record.overall_kg, 3) if record.overall_kg is not None else None,
                "rear_kg": _f(record.rear_axle_kg, 3),
                "total_kg": _f(record.cases[0].total_kg, 3),
            },
            "raw_readings": {wheel: [float(v) for v in values] for wheel, values in raw.items()},
            "spread_kg": {wheel: _f(max(values) - min(values), 3) for wheel, values in raw.items()},
            "calibration": calibration,
            "seats": [{"role": s["role"], "x_m": float(s["x_m"])} for s in config["seats"]],
            "load_items": [
                {"label": i["label"], "mass_kg": float(i["mass_kg"]), "x_m": float(i["x_m"])}
                for i in config["load_items"]
            ],
            "settings": {
                "occupant_mass_kg": float(record.occupant_mass_kg),
                "sum_tolerance": float(record.sum_tolerance),
                "rules_version": record.rules_version,
                "lsf_limit": record.axles.limit_text,
            },
            "cg_from_front_m": _f(record.cg_from_front_m, 4),
            "loading_cases": [
                {
                    "occupants": case.occupants,
                    "label": case_label(case.occupants),
                    "total_kg": _f(case.total_kg, 2),
                    "rear_kg": _f(case.rear_kg, 2),
                    "lsf": _f(case.lsf, 4),
                    "variance": _f(case.variance, 4),
                    "compliant": case.compliant,
                    "measured": case.measured,
                    "dynamics": case_figures(figures),
                }
                for case, figures in zip(record.cases, estimates.cases, strict=True)
            ],
            "dynamics_missing": list(estimates.missing),
        }
    )
