"""The pure stability core: weighbridge readings in, loading cases and an exact verdict out.

Imports nothing but the standard library, so every door (API, pages, CLI, PDF) shares one rule.
"""

from app.stability.errors import StabilityError
from app.stability.layout import DELTA, LAYOUT_NAMES, LAYOUTS, QUADRICYCLE, TADPOLE, Layout, layout_named
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
    rules_version,
)

__all__ = [
    "DELTA",
    "LAYOUTS",
    "LAYOUT_NAMES",
    "LSF_LIMIT",
    "QUADRICYCLE",
    "RULES_VERSION",
    "TADPOLE",
    "Assessment",
    "AssessmentInput",
    "Layout",
    "LoadItem",
    "LoadingCase",
    "MeasuredCase",
    "Rules",
    "Seat",
    "StabilityError",
    "WheelReadings",
    "assess",
    "case_label",
    "layout_named",
    "rules_version",
]
