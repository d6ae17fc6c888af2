"""API shapes of inspections: readings and occupants in, Table 4 and the verdict out."""

from __future__ import annotations

from datetime import date, datetime
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from app.api.fields import text
from app.dynamics.schemas import CaseDynamicsOut, CgHeight, CgLiftIn
from app.numbers import (
    LIMITS,
    MAX_LOAD_ITEMS,
    WHOLE_NUMBER,
    LoadKilograms,
    OccupantKilograms,
    OverallReading,
    Position,
    Wheelbase,
    WheelReading,
)
from app.vehicles.schemas import RegistrationNumber, SeatLayout

STUDY_EXAMPLE: dict[str, Any] = {
    "registration_number": "BDG 252 QH",
    "readings": {"front_kg": [108, 108, 108], "left_rear_kg": 115, "right_rear_kg": 135, "overall_kg": 359},
}


# The same weighing with the front wheel raised 0.40 m for the CG height (reference section 5).
STUDY_LIFT_EXAMPLE: dict[str, Any] = {
    **STUDY_EXAMPLE,
    "cg_lift": {"lift_height_m": 0.4, "front_kg": [94.8, 94.8]},
}


TADPOLE_EXAMPLE: dict[str, Any] = {
    "registration_number": "TDP 101 EV",
    "readings": {"left_front_kg": 186, "right_front_kg": 182, "rear_kg": 112, "overall_kg": 480},
}
QUADRICYCLE_EXAMPLE: dict[str, Any] = {
    "registration_number": "QDC 202 AA",
    "readings": {
        "left_front_kg": [150, 152],
        "right_front_kg": 148,
        "left_rear_kg": 140,
        "right_rear_kg": 143,
        "overall_kg": 582,
    },
}
_WHEELS_OF = (
    "The wheels read are those of the vehicle's axle layout: a delta's `front_kg`, `left_rear_kg`, "
    "`right_rear_kg`; a tadpole's `left_front_kg`, `right_front_kg`, `rear_kg`; a quadricycle's "
    "`left_front_kg`, `right_front_kg`, `left_rear_kg`, `right_rear_kg`. Each of them is required, and a "
    "wheel of another layout is refused (422, naming it and the vehicle's layout)."
)


class ReadingsIn(BaseModel):
    """One weighing: each wheel (and optionally the whole vehicle) read once or several times, in kg."""

    model_config = ConfigDict(extra="forbid", json_schema_extra={"description": _WHEELS_OF})

    front_kg: WheelReading | None = None
    left_rear_kg: WheelReading | None = None
    right_rear_kg: WheelReading | None = None
    left_front_kg: WheelReading | None = None
    right_front_kg: WheelReading | None = None
    rear_kg: WheelReading | None = None
    overall_kg: OverallReading | None = None


class OccupantsIn(BaseModel):
    """The occupant configuration; each part left out is taken from the vehicle and the settings."""

    model_config = ConfigDict(extra="forbid")

    mass_kg: OccupantKilograms | None = Field(default=None, description="Standard occupant mass (kg).")
    seats: SeatLayout | None = None


class LoadItemIn(BaseModel):
    """Extra mass carried in every loading case, `x_m` metres behind the front wheel centre."""

    model_config = ConfigDict(extra="forbid")

    label: Annotated[str, text(60)] = "load"
    mass_kg: LoadKilograms
    x_m: Position


class MeasuredCaseIn(BaseModel):
    """A loading case weighed directly with `occupants` persons (or ballast) aboard."""

    model_config = ConfigDict(extra="forbid")

    occupants: Annotated[int, Field(ge=1, le=LIMITS.max_seats), WHOLE_NUMBER]
    readings: ReadingsIn


class InspectionIn(BaseModel):
    """A weighbridge submission for a registered vehicle."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "examples": [STUDY_EXAMPLE, STUDY_LIFT_EXAMPLE, TADPOLE_EXAMPLE, QUADRICYCLE_EXAMPLE]
        },
    )

    registration_number: RegistrationNumber
    readings: ReadingsIn
    wheelbase_m: Wheelbase | None = None
    occupants: OccupantsIn | None = None
    load_items: list[LoadItemIn] = Field(default_factory=list, max_length=MAX_LOAD_ITEMS)
    measured_cases: list[MeasuredCaseIn] = Field(default_factory=list, max_length=LIMITS.max_seats)
    cg_lift: CgLiftIn | None = Field(
        default=None,
        description="For the estimates: the weighing with the front wheel raised (not with cg_height_m).",
    )
    cg_height_m: CgHeight | None = None


class LoadingCaseOut(BaseModel):
    """One row of Table 4; `compliant` is decided on the exact values, the figures are rounded."""

    occupants: int
    label: str
    total_kg: float
    rear_kg: float
    lsf: float
    variance: float
    compliant: bool
    measured: bool
    dynamics: CaseDynamicsOut | None = Field(
        default=None, description="Estimates beyond the static test; never part of the verdict."
    )


def _absent(value: object) -> bool:
    """A wheel the vehicle's layout does not have is left out of the answer."""
    return value is None


def _delta(value: object) -> bool:
    """The delta, the default layout, is left out: its answers are as they always were."""
    return value == "delta"


class AveragedReadingsOut(BaseModel):
    """The mean of each wheel's readings (kg) and the weight the cases start from.

    A delta's `front_kg`, `left_rear_kg`, `right_rear_kg`; a tadpole's `left_front_kg`,
    `right_front_kg` and `rear_kg` (its one rear wheel); a quadricycle's four. `rear_kg` is always the
    rear axle's load.
    """

    front_kg: float | None = Field(default=None, exclude_if=_absent)
    left_rear_kg: float | None = Field(default=None, exclude_if=_absent)
    right_rear_kg: float | None = Field(default=None, exclude_if=_absent)
    left_front_kg: float | None = Field(default=None, exclude_if=_absent)
    right_front_kg: float | None = Field(default=None, exclude_if=_absent)
    overall_kg: float | None
    rear_kg: float
    total_kg: float


class CalibrationOut(BaseModel):
    """The station scale's calibration in force when the readings were taken."""

    certificate: str | None
    valid_until: date | None


class SettingsOut(BaseModel):
    """The rules and settings in force when the inspection was decided."""

    occupant_mass_kg: float
    sum_tolerance: float
    lsf_limit: Literal["2/3", "1/3", "1/2"] = "2/3"
    rules_version: str


class InspectionSummary(BaseModel):
    """An inspection in a list."""

    id: int
    registration_number: str
    station: str | None
    created_at: datetime
    compliant: bool
    max_compliant_occupants: int


class InspectionOut(InspectionSummary):
    """A stored inspection: the inputs as received and Table 4 as decided."""

    vehicle_id: int
    layout: Literal["delta", "tadpole", "quadricycle"] = Field(
        default="delta",
        exclude_if=_delta,
        description="The vehicle's axle layout, which gives the wheels and the limit; left out for a "
        "delta (the default).",
    )
    wheelbase_m: float
    readings: AveragedReadingsOut
    raw_readings: dict[str, list[float]]
    spread_kg: dict[str, float] = Field(
        default_factory=dict,
        description="For each wheel (and the overall weight) of `raw_readings`: the largest minus the "
        "smallest reading, kg (0 for a single reading).",
    )
    calibration: CalibrationOut | None = Field(
        default=None, description="The scale calibration in force, when the station had one on record."
    )
    seats: list[dict[str, float | str]]
    load_items: list[dict[str, float | str]]
    settings: SettingsOut
    cg_from_front_m: float
    loading_cases: list[LoadingCaseOut]
    dynamics_missing: list[str] = Field(
        default_factory=list, description="The inputs whose absence leaves estimates in `dynamics` null."
    )


class InspectionPage(BaseModel):
    """One page of inspections, newest first."""

    items: list[InspectionSummary]
    total: int
    limit: int
    offset: int
