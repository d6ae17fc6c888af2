"""API shapes of vehicles: registration with a seat layout."""

from __future__ import annotations

from datetime import datetime
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from app.numbers import Position, Wheelbase


class SeatIn(BaseModel):
    """A seat: who sits there and how far behind the front wheel centre (m)."""

    model_config = ConfigDict(extra="forbid")

    role: Literal["driver", "passenger"]
    x_m: Position


class VehicleIn(BaseModel):
    """A tricycle to register."""

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
                        {"role": "driver", "x_m": 0.9303},
                        {"role": "passenger", "x_m": 1.6303},
                        {"role": "passenger", "x_m": 1.6303},
                        {"role": "passenger", "x_m": 1.6303},
                    ],
                }
            ]
        },
    )

    registration_number: str = Field(min_length=2, max_length=32, pattern=r"^[A-Za-z0-9][A-Za-z0-9 \-]*$")
    make: str = Field(min_length=1, max_length=80)
    model: str = Field(min_length=1, max_length=80)
    model_year: int | None = Field(default=None, ge=1950, le=2100)
    chassis_number: str | None = Field(default=None, min_length=1, max_length=64)
    wheelbase_m: Wheelbase
    seats: list[SeatIn] = Field(min_length=1, max_length=12)


class VehicleOut(BaseModel):
    """A registered vehicle."""

    id: int
    registration_number: str
    make: str
    model: str
    model_year: int | None
    chassis_number: str | None
    wheelbase_m: float
    seats: list[SeatOut]
    created_at: datetime


class SeatOut(BaseModel):
    """A stored seat."""

    role: Literal["driver", "passenger"]
    x_m: float
