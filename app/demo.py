"""The study's vehicle and its inspection, so a newcomer sees Table 4 at once."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from sqlalchemy.orm import Session

from app.config import Settings
from app.inspections.models import Inspection
from app.inspections.service import InspectionRequest, record_inspection
from app.stability import WheelReadings
from app.stations.service import create_station
from app.vehicles.service import find_vehicle, register_vehicle

STUDY_REGISTRATION = "BDG 252 QH"
DEMO_STATION = "Demo weighbridge (Agbara)"
DRIVER_X_M = Decimal("0.9303")
PASSENGER_X_M = Decimal("1.6303")
STUDY_SEATS = [("driver", DRIVER_X_M)] + [("passenger", PASSENGER_X_M)] * 3
# Asuelinmen, Ojolo, Ajayi, Tables 1-3: a = 108, b = 115, c = 135, W = 359 kg, WB = 2.000 m.
STUDY_READINGS = WheelReadings(
    front_kg=(Decimal("108"),),
    left_rear_kg=(Decimal("115"),),
    right_rear_kg=(Decimal("135"),),
    overall_kg=(Decimal("359"),),
)


@dataclass(frozen=True)
class DemoResult:
    """What `trikecert demo` made (or found)."""

    inspection: Inspection | None
    station_key: str | None
    created: bool


def load_demo(session: Session, settings: Settings) -> DemoResult:
    """Register the study's vehicle, a demo station and the study's inspection, once."""
    if find_vehicle(session, STUDY_REGISTRATION) is not None:
        return DemoResult(inspection=None, station_key=None, created=False)
    register_vehicle(
        session,
        registration_number=STUDY_REGISTRATION,
        make="Bajaj",
        model="RE 2-stroke (study vehicle)",
        model_year=2012,
        chassis_number=None,
        wheelbase_m=Decimal("2.000"),
        seats=STUDY_SEATS,
    )
    station, key = create_station(session, name=DEMO_STATION)
    inspection = record_inspection(
        session,
        request=InspectionRequest(registration_number=STUDY_REGISTRATION, readings=STUDY_READINGS),
        rules=settings.rules(),
        station=station,
    )
    return DemoResult(inspection=inspection, station_key=key, created=True)
