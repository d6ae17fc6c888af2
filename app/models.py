"""Imports every ORM model so the metadata is complete (for Alembic and the tests)."""

from app.accounts.models import LoginAttempt, User, UserSession
from app.db import Base
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.stations.models import Station
from app.vehicles.models import Seat, Vehicle
from app.web.models import FormSubmission

__all__ = [
    "Base",
    "FormSubmission",
    "Inspection",
    "LoadingCaseRow",
    "LoginAttempt",
    "Reading",
    "Seat",
    "Station",
    "User",
    "UserSession",
    "Vehicle",
]
