"""Imports every ORM model so the metadata is complete (for Alembic and the tests)."""

from app.accounts.models import User
from app.db import Base
from app.inspections.models import Inspection, LoadingCaseRow, Reading
from app.stations.models import Station
from app.vehicles.models import Seat, Vehicle

__all__ = ["Base", "Inspection", "LoadingCaseRow", "Reading", "Seat", "Station", "User", "Vehicle"]
