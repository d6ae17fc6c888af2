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

# The reference's section 7: three vehicles of the study's model with made-up readings whose means
# are the study's Table 2 (front, left rear, right rear, overall in kg).
STUDY_TYPE_READINGS: dict[str, dict[str, Any]] = {
    "BDG 252 QH": {"front_kg": 106, "left_rear_kg": 114, "right_rear_kg": 136, "overall_kg": 357},
    "AGL 7180": {"front_kg": 110, "left_rear_kg": 116, "right_rear_kg": 133, "overall_kg": 360},
    "AGL 532 QH": {"front_kg": 108, "left_rear_kg": 115, "right_rear_kg": 136, "overall_kg": 360},
}
# What the type assessment of those three answers: the study's Table 4 and section 7's spread.
STUDY_TYPE_TABLE = [
    (0, 359.0, 250.0, 0.6964, -0.0297, False),
    (1, 431.0, 283.49, 0.6578, 0.0089, True),
    (2, 503.0, 342.18, 0.6803, -0.0136, False),
    (3, 575.0, 400.87, 0.6972, -0.0305, False),
    (4, 647.0, 459.56, 0.7103, -0.0436, False),
]
STUDY_TYPE_SPREAD = [
    (0, 0.69167, 0.69639, 0.70028, 0.00437, 0.70375, False),
    (1, 0.65391, 0.65776, 0.66082, 0.00352, 0.66369, True),
    (2, 0.67695, 0.68029, 0.683, 0.00307, 0.68547, False),
    (3, 0.69422, 0.69717, 0.6996, 0.00273, 0.70177, False),
    (4, 0.70766, 0.7103, 0.7125, 0.00245, 0.71443, False),
]
