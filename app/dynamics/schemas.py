"""API shapes of the estimates beyond the static test: a vehicle's figures (all optional: only the estimates
need them), an inspection's CG-height weighing in, the figures out."""

from __future__ import annotations

from decimal import Decimal
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, TypeAdapter, WithJsonSchema

from app.numbers import MAX_READINGS, Kilograms, number_only, number_schema, one_or_many, readings_schema
from app.stability.dynamics import BOUNDS, SEAT_HEIGHT_M

# Decimal places accepted for each figure (metres to 0.1 mm, stiffness to 0.1 N/rad).
DECIMALS = {
    "track_m": 4,
    "front_track_m": 4,
    "wheel_radius_m": 4,
    "front_cornering_stiffness_n_per_rad": 1,
    "rear_cornering_stiffness_n_per_rad": 1,
    "drag_area_m2": 4,
    "centre_of_pressure_height_m": 4,
    "cg_height_m": 4,
    "cg_lift.lift_height_m": 4,
    "cg_lift.front_kg": 3,
}
UNITS = {
    "track_m": "m",
    "front_track_m": "m",
    "wheel_radius_m": "m",
    "front_cornering_stiffness_n_per_rad": "N/rad per tyre",
    "rear_cornering_stiffness_n_per_rad": "N/rad per tyre",
    "drag_area_m2": "m²",
    "centre_of_pressure_height_m": "m",
    "cg_height_m": "m",
    "cg_lift.lift_height_m": "m",
    "cg_lift.front_kg": "kg",
}


def _bounds(name: str) -> tuple[Decimal, Decimal]:
    low, high, _ = BOUNDS[name]
    return Decimal(str(low)), Decimal(str(high))


def figure_field(name: str, description: str) -> Any:
    """Pydantic's bounds of one figure: the core's (exclusive minimum, inclusive maximum) and its decimals."""
    low, high = _bounds(name)
    return Field(gt=low, le=high, allow_inf_nan=False, decimal_places=DECIMALS[name], description=description)


def figure_schema(name: str, description: str) -> WithJsonSchema:
    """The JSON schema of one figure: a bounded number given to at most its decimals."""
    low, high = _bounds(name)
    return WithJsonSchema(
        {**number_schema(low, high, exclusive=True, decimals=DECIMALS[name]), "description": description}
    )


_TRACK = (
    "Rear track, for two rear wheels (delta, quadricycle): between the centres of the rear tyres' "
    "contact patches (m); a tadpole's one rear wheel has none."
)
_FRONT_TRACK = (
    "Front track, for two front wheels (tadpole, quadricycle): between the centres of the front tyres' "
    "contact patches (m)."
)
_RADIUS = "Loaded rear wheel radius: axle centre to the ground (m)."
_FRONT = "Cornering stiffness of the front tyre, of each front tyre where there are two (N/rad)."
_REAR = "Cornering stiffness of each rear tyre, of the one rear tyre on a tadpole (N/rad)."
_DRAG = "Drag coefficient times frontal area, Cd x A (m²)."
_PRESSURE = "Height of the centre of pressure above the ground (m)."
_ONLY_NUMBERS = BeforeValidator(number_only)
Track = Annotated[Decimal, _ONLY_NUMBERS, figure_field("track_m", _TRACK), figure_schema("track_m", _TRACK)]
FrontTrack = Annotated[
    Decimal,
    _ONLY_NUMBERS,
    figure_field("front_track_m", _FRONT_TRACK),
    figure_schema("front_track_m", _FRONT_TRACK),
]
WheelRadius = Annotated[
    Decimal, _ONLY_NUMBERS, figure_field("wheel_radius_m", _RADIUS), figure_schema("wheel_radius_m", _RADIUS)
]
FrontStiffness = Annotated[
    Decimal,
    _ONLY_NUMBERS,
    figure_field("front_cornering_stiffness_n_per_rad", _FRONT),
    figure_schema("front_cornering_stiffness_n_per_rad", _FRONT),
]
RearStiffness = Annotated[
    Decimal,
    _ONLY_NUMBERS,
    figure_field("rear_cornering_stiffness_n_per_rad", _REAR),
    figure_schema("rear_cornering_stiffness_n_per_rad", _REAR),
]
DragArea = Annotated[
    Decimal, _ONLY_NUMBERS, figure_field("drag_area_m2", _DRAG), figure_schema("drag_area_m2", _DRAG)
]
PressureHeight = Annotated[
    Decimal,
    _ONLY_NUMBERS,
    figure_field("centre_of_pressure_height_m", _PRESSURE),
    figure_schema("centre_of_pressure_height_m", _PRESSURE),
]
SeatHeight = Annotated[
    Decimal,
    BeforeValidator(number_only),
    Field(ge=Decimal(str(SEAT_HEIGHT_M[0])), le=Decimal(str(SEAT_HEIGHT_M[1])), allow_inf_nan=False),
    WithJsonSchema(
        {
            **number_schema(
                Decimal(str(SEAT_HEIGHT_M[0])), Decimal(str(SEAT_HEIGHT_M[1])), exclusive=False, decimals=4
            ),
            "description": "Seated person's CG above the ground (m), some 0.2 m above the seat top.",
        }
    ),
    Field(decimal_places=4),
]


def type_schema(kind: Any) -> dict[str, Any]:
    """The JSON schema of an annotated type, for hand-written schemas that embed it."""
    schema: dict[str, Any] = TypeAdapter(kind).json_schema()
    return schema


class VehicleDynamicsIn(BaseModel):
    """The figures beyond the weighing; each may be left out (its estimates are then unknown)."""

    track_m: Track | None = None
    wheel_radius_m: WheelRadius | None = None
    front_cornering_stiffness_n_per_rad: FrontStiffness | None = None
    rear_cornering_stiffness_n_per_rad: RearStiffness | None = None
    drag_area_m2: DragArea | None = None
    centre_of_pressure_height_m: PressureHeight | None = None
    front_track_m: FrontTrack | None = None


class VehicleDynamicsOut(BaseModel):
    """The vehicle's figures in force: revision 1 at registration, one more for every change."""

    revision: int
    track_m: float | None
    wheel_radius_m: float | None
    seat_heights_m: list[float | None]
    front_cornering_stiffness_n_per_rad: float | None
    rear_cornering_stiffness_n_per_rad: float | None
    drag_area_m2: float | None
    centre_of_pressure_height_m: float | None
    front_track_m: float | None = Field(
        default=None,
        # A vehicle with one front wheel has no front track: the key is left out rather than null.
        exclude_if=lambda value: value is None,
        description="The front track of two front wheels (tadpole, quadricycle), when recorded (m).",
    )


_LIFT = "How far the front wheel (two front wheels: the front axle) is raised for the second weighing (m)."
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
            "description": "The front wheel reaction with the wheel raised (kg), two front wheels' together "
            "with the axle raised: one reading, or a list of repeated readings that are averaged.",
        }
    ),
]


class CgLiftIn(BaseModel):
    """The axle-lift weighing: the front axle raised by `lift_height_m`, its reaction read again."""

    model_config = ConfigDict(extra="forbid")

    lift_height_m: LiftHeight
    front_kg: RaisedFrontReading


class CaseDynamicsOut(BaseModel):
    """Estimates for one loading case (not part of the verdict); null where an input is unknown."""

    cg_height_m: float | None = Field(description="Centre of gravity height of the case (m).")
    rollover_threshold_g: float | None = Field(
        description="Static rollover threshold y / h (g), y the tipping axis's distance from the centre line "
        "at the CG: (T / 2h) LSF on a delta, (T_f / 2h)(1 - LSF) on a tadpole, T / 2h on a quadricycle with "
        "equal tracks."
    )
    tilt_angle_deg: float | None = Field(description="Tilt-table angle at which it would tip (degrees).")
    understeer_margin_nm_per_rad: float | None = Field(
        description="S = n_r L2 CaR - n_f L1 CaF (N m/rad), 2 L2 CaR - L1 CaF on a delta: positive "
        "understeers at every speed."
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
    compliant_at_speed: bool | None = Field(
        description="Whether the LSF at speed is below the layout's limit (2/3 delta, 1/3 tadpole, "
        "1/2 quadricycle) (estimate)."
    )
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
    front_track_m: float | None = Field(
        default=None,
        # A vehicle with one front wheel has no front track: the key is left out rather than null.
        exclude_if=lambda value: value is None,
        description="The front track of two front wheels (tadpole, quadricycle), when recorded (m).",
    )

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
