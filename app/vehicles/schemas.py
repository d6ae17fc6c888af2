"""API shapes of vehicles: registration with a seat layout."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, WithJsonSchema

from app.api.fields import identifier, text
from app.dynamics.schemas import SeatHeight, VehicleDynamicsIn, VehicleDynamicsOut, type_schema
from app.numbers import LIMITS, POSITION_SCHEMA, WHOLE_NUMBER, Position, Wheelbase

# 2 to 16 letters and digits, with spaces or hyphens between them that are ignored:
# exactly the registrations the service can normalise (`bdg-252qh` and `BDG 252 QH` are one vehicle).
REGISTRATION_PATTERN = r"^[A-Za-z0-9](?:[ \-]*[A-Za-z0-9]){1,15}$"
REGISTRATION_DESCRIPTION = (
    "2 to 16 letters and digits; spaces and hyphens between them are ignored, as is case "
    "(`bdg-252qh` is `BDG 252 QH`)."
)
REGISTRATION_WORDS = "use 2 to 16 letters and digits, like BDG 252 QH (spaces and hyphens are ignored)"
REGISTRATION_RULE = identifier(
    REGISTRATION_PATTERN,
    min_length=2,
    max_length=32,
    words=REGISTRATION_WORDS,
    description=REGISTRATION_DESCRIPTION,
)
RegistrationNumber = Annotated[str, REGISTRATION_RULE]


def _seat_schema(role: str, **more: dict[str, Any]) -> dict[str, Any]:
    return {
        "type": "object",
        "properties": {"role": {"const": role}, "x_m": POSITION_SCHEMA, **more},
        "required": ["role", "x_m"],
        "additionalProperties": False,
    }


# The driver's seat first, then the passengers' (the loading cases add occupants in this order).
SEAT_LAYOUT_SCHEMA: dict[str, Any] = {
    "type": "array",
    "prefixItems": [_seat_schema("driver")],
    "items": _seat_schema("passenger"),
    "minItems": 1,
    "maxItems": LIMITS.max_seats,
    "description": (
        "The seats, driver first, each `x_m` metres behind the front wheel centre; a seat may sit at "
        "most 1 m ahead of the front wheel or behind the rear axle (x_m <= wheelbase_m + 1)."
    ),
}


class SeatIn(BaseModel):
    """A seat: who sits there and how far behind the front wheel centre (m)."""

    model_config = ConfigDict(extra="forbid")

    role: Literal["driver", "passenger"]
    x_m: Position


SeatLayout = Annotated[
    list[SeatIn], Field(min_length=1, max_length=LIMITS.max_seats), WithJsonSchema(SEAT_LAYOUT_SCHEMA)
]


class VehicleSeatIn(SeatIn):
    """A registered seat may also give its occupant's seated CG height `z_m` (for the estimates)."""

    z_m: SeatHeight | None = None


_Z = {"z_m": type_schema(SeatHeight)}
VehicleSeatLayout = Annotated[
    list[VehicleSeatIn],
    Field(min_length=1, max_length=LIMITS.max_seats),
    WithJsonSchema(
        {
            **SEAT_LAYOUT_SCHEMA,
            "prefixItems": [_seat_schema("driver", **_Z)],
            "items": _seat_schema("passenger", **_Z),
            "description": SEAT_LAYOUT_SCHEMA["description"]
            + " Each may give `z_m`, the seated person's centre of gravity above the ground (m).",
        }
    ),
]


LAYOUT_DESCRIPTION = (
    "The axle layout, fixed at registration (a vehicle rebuilt with other axles is registered anew): "
    "`delta` (one front wheel, two rear; the default), `tadpole` (two front, one rear) or `quadricycle` "
    "(two front, two rear). It sets the wheels an inspection reads and the limit of the LSF: 2/3, 1/3, 1/2."
)
# Like a seat's role: an enumeration, not free text (the text rule's walk of the API skips it).
LayoutField = Annotated[
    Literal["delta", "tadpole", "quadricycle"],
    WithJsonSchema({"enum": ["delta", "tadpole", "quadricycle"], "description": LAYOUT_DESCRIPTION}),
]

TADPOLE_VEHICLE_EXAMPLE: dict[str, Any] = {
    "registration_number": "TDP 101 EV",
    "layout": "tadpole",
    "make": "Example",
    "model": "E-Tadpole",
    "wheelbase_m": 1.9,
    "seats": [
        {"role": "driver", "x_m": 0.7},
        {"role": "passenger", "x_m": 1.35},
        {"role": "passenger", "x_m": 1.35},
        {"role": "passenger", "x_m": 1.35},
    ],
}
QUADRICYCLE_VEHICLE_EXAMPLE: dict[str, Any] = {
    "registration_number": "QDC 202 AA",
    "layout": "quadricycle",
    "make": "Bajaj",
    "model": "Qute",
    "wheelbase_m": 1.925,
    "seats": [
        {"role": "driver", "x_m": 0.95},
        {"role": "passenger", "x_m": 1.75},
        {"role": "passenger", "x_m": 1.75},
        {"role": "passenger", "x_m": 1.75},
    ],
}


class VehicleIn(VehicleDynamicsIn):
    """A tricycle to register; the figures for the estimates beyond the static test are optional."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "examples": [
                {
                    "registration_number": "BDG 252 QH",
                    "make": "Bajaj",
                    "model": "RE 4S",
                    "model_year": 2012,
                    "chassis_number": "MD2AAC4ZZCWB12345",
                    "wheelbase_m": 2.0,
                    "seats": [
                        {"role": "driver", "x_m": 0.9303, "z_m": 0.75},
                        {"role": "passenger", "x_m": 1.6303, "z_m": 0.80},
                        {"role": "passenger", "x_m": 1.6303, "z_m": 0.80},
                        {"role": "passenger", "x_m": 1.6303, "z_m": 0.80},
                    ],
                    "track_m": 1.15,
                    "wheel_radius_m": 0.19,
                    "front_cornering_stiffness_n_per_rad": 8000,
                    "rear_cornering_stiffness_n_per_rad": 8000,
                    "drag_area_m2": 1.6,
                    "centre_of_pressure_height_m": 0.9,
                },
                TADPOLE_VEHICLE_EXAMPLE,
                QUADRICYCLE_VEHICLE_EXAMPLE,
            ]
        },
    )

    registration_number: RegistrationNumber
    layout: LayoutField = "delta"
    make: Annotated[str, text(80)]
    model: Annotated[str, text(80)]
    model_year: Annotated[int, Field(ge=1950, le=2100), WHOLE_NUMBER] | None = None
    chassis_number: Annotated[str, text(64)] | None = None
    wheelbase_m: Wheelbase
    seats: VehicleSeatLayout


class VehicleOut(BaseModel):
    """A registered vehicle."""

    id: int
    registration_number: str
    layout: Annotated[
        Literal["delta", "tadpole", "quadricycle"],
        Field(
            exclude_if=lambda value: value == "delta",
            description="The axle layout, fixed at registration; left out for a delta (the default).",
        ),
    ] = "delta"
    make: str
    model: str
    model_year: int | None
    chassis_number: str | None
    wheelbase_m: float
    seats: list[SeatOut]
    dynamics: VehicleDynamicsOut | None = Field(
        default=None,
        description="The figures for the estimates in force; null for a vehicle registered before.",
    )
    created_at: datetime


class SeatOut(BaseModel):
    """A stored seat."""

    role: Literal["driver", "passenger"]
    x_m: float
