"""The pure stability core: weighbridge readings in, loading cases and an exact verdict out.

Imports nothing but the standard library, so every door (API, pages, CLI, PDF) shares one rule.
"""

from app.stability.errors import StabilityError
from app.stability.lsf import assess
from app.stability.model import (
    LSF_LIMIT,
    RULES_VERSION,
    Assessment,
    AssessmentInput,
    LoadingCase,
    LoadItem,
    MeasuredCase,
    Rules,
    Seat,
    WheelReadings,
    case_label,
)

__all__ = [
    "LSF_LIMIT",
    "RULES_VERSION",
    "Assessment",
    "AssessmentInput",
    "LoadItem",
    "LoadingCase",
    "MeasuredCase",
    "Rules",
    "Seat",
    "StabilityError",
    "WheelReadings",
    "assess",
    "case_label",
]
