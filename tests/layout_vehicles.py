"""A tadpole and a quadricycle with every figure the estimates need (tracks, seat heights), and the
readings they are weighed with: shared by the tests of the API and of the page and the paper."""

from __future__ import annotations

from typing import Any

SEAT_Z = 0.75  # every seat's seated height, as registered below
TADPOLE: dict[str, Any] = {
    "registration_number": "TDP 101 EV",
    "layout": "tadpole",
    "make": "Example",
    "model": "E-Tadpole",
    "wheelbase_m": 1.9,
    "front_track_m": 1.2,
    "seats": [
        {"role": "driver", "x_m": 0.7, "z_m": SEAT_Z},
        *[{"role": "passenger", "x_m": 1.35, "z_m": SEAT_Z}] * 3,
    ],
}
TADPOLE_READINGS = {"left_front_kg": 186, "right_front_kg": 182, "rear_kg": 112}
QUADRICYCLE: dict[str, Any] = {
    "registration_number": "QDC 202 AA",
    "layout": "quadricycle",
    "make": "Bajaj",
    "model": "Qute",
    "wheelbase_m": 2.0,
    "front_track_m": 1.3,
    "track_m": 1.3,
    "seats": [
        {"role": "driver", "x_m": 1.0, "z_m": SEAT_Z},
        {"role": "passenger", "x_m": 1.8, "z_m": SEAT_Z},
    ],
}
QUADRICYCLE_READINGS = {"left_front_kg": 120, "right_front_kg": 118, "left_rear_kg": 90, "right_rear_kg": 92}
