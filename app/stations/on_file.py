"""What an inspection needs of the station that weighed it, as a plain value (not an ORM row)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import date
from decimal import Decimal

from app.stations.models import Station


@dataclass(frozen=True)
class StationOnFile:
    """A station's name and its scale: calibration certificate and validity, capacity and division (kg)."""

    id: int
    name: str
    calibration_certificate: str | None = None
    calibration_valid_until: date | None = None
    capacity_kg: Decimal | None = None
    division_kg: Decimal | None = None

    @classmethod
    def of(cls, station: Station) -> StationOnFile:
        """The value of a station row."""
        return cls(
            id=station.id,
            name=station.name,
            calibration_certificate=station.calibration_certificate,
            calibration_valid_until=station.calibration_valid_until,
            capacity_kg=station.capacity_kg,
            division_kg=station.division_kg,
        )
