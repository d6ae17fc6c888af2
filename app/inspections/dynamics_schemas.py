"""API shapes of the estimates beyond the static test: the CG-height weighing in, the figures out."""

from __future__ import annotations

from decimal import Decimal
from typing import Annotated

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, WithJsonSchema

from app.numbers import MAX_READINGS, Kilograms, number_only, number_schema, one_or_many, readings_schema
from app.vehicles.dynamics_schemas import figure_field, figure_schema

_LIFT = "How far the front wheel is raised for the second weighing (m)."
_CG = "The empty vehicle's centre of gravity height above the ground (m), if known (not with cg_lift)."
LiftHeight = Annotated[
    Decimal,
    BeforeValidator(number_only),
    figure_field("cg_lift.lift_height_m", _LIFT),
    figure_schema("cg_lift.lift_height_m", _LIFT),
]
CgHeight = Annotated[
    Decimal, BeforeValidator(number_only), figure_field("cg_height_m", _CG), figure_schema("cg_height_m", _CG)
]
_RAISED = number_schema(Decimal(0), Decimal(1500), exclusive=True, decimals=3)
RaisedFrontReading = Annotated[
    list[Annotated[Kilograms, Field(decimal_places=3)]],
    BeforeValidator(one_or_many),
    Field(min_length=1, max_length=MAX_READINGS),
    WithJsonSchema(
        {
            **readings_schema(_RAISED),
            "description": "The front wheel reaction with the wheel raised (kg): one reading, or a list "
            "of repeated readings that are averaged.",
        }
    ),
]


class CgLiftIn(BaseModel):
    """The axle-lift weighing: the front wheel raised by `lift_height_m`, its reaction read again."""

    model_config = ConfigDict(extra="forbid")

    lift_height_m: LiftHeight
    front_kg: RaisedFrontReading


class CaseDynamicsOut(BaseModel):
    """Estimates for one loading case (not part of the verdict); null where an input is unknown."""

    cg_height_m: float | None = Field(description="Centre of gravity height of the case (m).")
    rollover_threshold_g: float | None = Field(description="Static rollover threshold (T / 2h) LSF (g).")
    tilt_angle_deg: float | None = Field(description="Tilt-table angle at which it would tip (degrees).")
    understeer_margin_nm_per_rad: float | None = Field(
        description="S = 2 L2 CaR - L1 CaF (N m/rad): positive understeers at every speed."
    )
    critical_speed_kmh: float | None = Field(
        description="Speed above which an oversteering case turns unstable (km/h); null when S > 0."
    )


class CaseAtSpeedOut(CaseDynamicsOut):
    """A loading case's estimates, also driven at the speed and acceleration asked for."""

    occupants: int
    label: str
    lsf: float
    compliant: bool = Field(description="The static verdict, as stored; never changed by an estimate.")
    lsf_at_speed: float | None = Field(description="LSF with drag and acceleration moving load rearward.")
    compliant_at_speed: bool | None = Field(description="Whether the LSF at speed is below 2/3 (estimate).")
    margin_speed_kmh: float | None = Field(
        description="Speed at which drag alone uses up the static margin (km/h); null for a case NC at rest."
    )


class DynamicsInputsOut(BaseModel):
    """The inputs the estimates used, shown beside them."""

    vehicle_revision: int | None = Field(
        description="The revision of the vehicle's figures; null: none on file."
    )
    track_m: float | None
    wheel_radius_m: float | None
    seat_heights_m: list[float | None]
    front_cornering_stiffness_n_per_rad: float | None
    rear_cornering_stiffness_n_per_rad: float | None
    drag_area_m2: float | None
    centre_of_pressure_height_m: float | None
    cg_lift_height_m: float | None
    cg_lift_front_kg: float | None = Field(description="The mean of the raised front readings (kg).")
    cg_height_given_m: float | None
    empty_cg_height_m: float | None = Field(description="The empty vehicle's CG height used (m).")
    air_density_kg_m3: float
    g_ms2: float


class DynamicsOut(BaseModel):
    """Estimates beyond the static test for one inspection, at a speed and acceleration."""

    inspection_id: int
    speed_kmh: float
    acceleration_ms2: float
    inputs: DynamicsInputsOut
    missing: list[str] = Field(description="The inputs whose absence leaves figures null.")
    loading_cases: list[CaseAtSpeedOut]
