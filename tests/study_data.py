"""The study's vehicle and readings as API bodies, shared by the HTTP tests."""

from __future__ import annotations

from typing import Any

STUDY_VEHICLE: dict[str, Any] = {
    "registration_number": "BDG 252 QH",
    "make": "Bajaj",
    "model": "RE",
    "model_year": 2012,
    "wheelbase_m": 2.0,
    "seats": [
        {"role": "driver", "x_m": 0.9303},
        {"role": "passenger", "x_m": 1.6303},
        {"role": "passenger", "x_m": 1.6303},
        {"role": "passenger", "x_m": 1.6303},
    ],
}
STUDY_READINGS: dict[str, Any] = {
    "front_kg": 108,
    "left_rear_kg": 115,
    "right_rear_kg": 135,
    "overall_kg": 359,
}
