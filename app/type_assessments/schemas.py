"""API shapes of type assessments: the model asked for, and the stored outcome."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

from app.api.fields import text
from app.api.limits import MAX_LIST_ITEMS
from app.ids import MAX_ID
from app.numbers import WHOLE_NUMBER

InspectionRef = Annotated[int, Field(ge=1, le=MAX_ID), WHOLE_NUMBER]


class TypeAssessmentIn(BaseModel):
    """A make and model to assess; without `inspection_ids`, the latest inspection of every vehicle."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "examples": [
                {"make": "Bajaj", "model": "RE", "model_year": 2012},
                {"make": "Bajaj", "model": "RE", "inspection_ids": [101, 102, 103]},
            ]
        },
    )

    make: Annotated[str, text(80)]
    model: Annotated[str, text(80)]
    model_year: Annotated[int, Field(ge=1950, le=2100), WHOLE_NUMBER] | None = None
    inspection_ids: (
        Annotated[
            list[InspectionRef],
            Field(
                min_length=2,
                max_length=MAX_LIST_ITEMS,  # more vehicles: leave the ids out (the latest of each)
                description="The inspections to use, one per vehicle (default: each vehicle's latest)",
                json_schema_extra={"uniqueItems": True},  # an id twice is refused (one_per_vehicle)
            ),
        ]
        | None
    ) = None


class VehicleCaseOut(BaseModel):
    """One vehicle's own LSF and verdict in one loading case."""

    occupants: int
    lsf: float
    compliant: bool


class TypeVehicleOut(BaseModel):
    """A vehicle of the type and the inspection used."""

    registration_number: str
    inspection_id: int
    cases: list[VehicleCaseOut]


class TypeTableRowOut(BaseModel):
    """A row of the type's Table 4, from the mean readings (the study's method)."""

    occupants: int
    total_kg: float
    rear_kg: float
    lsf: float
    variance: float
    compliant: bool


class TypeSpreadOut(BaseModel):
    """One loading case across the vehicles: min, mean, max, sample standard deviation, 95 % bound."""

    occupants: int
    min_lsf: float
    mean_lsf: float
    max_lsf: float
    sd_lsf: float
    upper_95_lsf: float
    confident_compliant: bool


class TypeAssessmentOut(BaseModel):
    """A stored type assessment; `compliant` and `max_compliant_occupants` follow the confident verdict."""

    model_config = ConfigDict(
        json_schema_extra={
            "examples": [
                {
                    "id": 1,
                    "vehicles": [
                        {
                            "registration_number": "AGL 532 QH",
                            "inspection_id": 103,
                            "cases": [
                                {"occupants": 0, "lsf": 0.69722, "compliant": False},
                                {"occupants": 1, "lsf": 0.65854, "compliant": True},
                            ],
                        }
                    ],
                    "table": [
                        {
                            "occupants": 0,
                            "total_kg": 359.0,
                            "rear_kg": 250.0,
                            "lsf": 0.6964,
                            "variance": -0.0297,
                            "compliant": False,
                        },
                        {
                            "occupants": 1,
                            "total_kg": 431.0,
                            "rear_kg": 283.49,
                            "lsf": 0.6578,
                            "variance": 0.0089,
                            "compliant": True,
                        },
                    ],
                    "spread": [
                        {
                            "occupants": 0,
                            "min_lsf": 0.69167,
                            "mean_lsf": 0.69639,
                            "max_lsf": 0.70028,
                            "sd_lsf": 0.00437,
                            "upper_95_lsf": 0.70375,
                            "confident_compliant": False,
                        },
                        {
                            "occupants": 1,
                            "min_lsf": 0.65391,
                            "mean_lsf": 0.65776,
                            "max_lsf": 0.66082,
                            "sd_lsf": 0.00352,
                            "upper_95_lsf": 0.66369,
                            "confident_compliant": True,
                        },
                    ],
                    "compliant": False,
                    "max_compliant_occupants": 1,
                }
            ]
        }
    )

    id: int
    vehicles: list[TypeVehicleOut]
    table: list[TypeTableRowOut]
    spread: list[TypeSpreadOut]
    compliant: bool
    max_compliant_occupants: int
