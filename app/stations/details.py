"""A station's particulars and its scale: location, contact, calibration, capacity and division."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import date
from decimal import Decimal

from app.errors import InvalidInput
from app.stations.models import Station
from app.text import optional_checked

MAX_CAPACITY_KG = Decimal("100000")
KG_DECIMALS = 3
_TEXT_LIMITS = {"location": 200, "operator_contact": 200, "calibration_certificate": 64}


@dataclass(frozen=True)
class StationDetails:
    """Everything about a station but its name and key; None means not on record."""

    location: str | None = None
    operator_contact: str | None = None
    calibration_certificate: str | None = None
    calibration_valid_until: date | None = None
    capacity_kg: Decimal | None = None
    division_kg: Decimal | None = None


def details_of(station: Station) -> StationDetails:
    """The particulars on record for a station (to change some and keep the rest)."""
    return StationDetails(
        location=station.location,
        operator_contact=station.operator_contact,
        calibration_certificate=station.calibration_certificate,
        calibration_valid_until=station.calibration_valid_until,
        capacity_kg=station.capacity_kg,
        division_kg=station.division_kg,
    )


def _clean_text(field: str, value: str | None) -> str | None:
    text = optional_checked(field, value, max_length=_TEXT_LIMITS[field])
    return " ".join(text.split()) if text else None


def _check_kg(field: str, value: Decimal | None, *, maximum: Decimal) -> None:
    if value is None:
        return
    exponent = value.as_tuple().exponent
    if not value.is_finite() or value <= 0 or value > maximum:
        raise InvalidInput(
            f"{field}: give a weight above 0 and at most {maximum} kg; got {value}", field=field, rule="range"
        )
    if isinstance(exponent, int) and -exponent > KG_DECIMALS:
        raise InvalidInput(
            f"{field}: give the weight to at most {KG_DECIMALS} decimal places", field=field, rule="precision"
        )


def checked_details(details: StationDetails) -> StationDetails:
    """The details with text tidied (blank means none); InvalidInput names the first bad field."""
    _check_kg("capacity_kg", details.capacity_kg, maximum=MAX_CAPACITY_KG)
    _check_kg("division_kg", details.division_kg, maximum=details.capacity_kg or MAX_CAPACITY_KG)
    return StationDetails(
        location=_clean_text("location", details.location),
        operator_contact=_clean_text("operator_contact", details.operator_contact),
        calibration_certificate=_clean_text("calibration_certificate", details.calibration_certificate),
        calibration_valid_until=details.calibration_valid_until,
        capacity_kg=details.capacity_kg,
        division_kg=details.division_kg,
    )


def apply_details(station: Station, details: StationDetails) -> None:
    """Copy checked details onto the station row."""
    station.location = details.location
    station.operator_contact = details.operator_contact
    station.calibration_certificate = details.calibration_certificate
    station.calibration_valid_until = details.calibration_valid_until
    station.capacity_kg = details.capacity_kg
    station.division_kg = details.division_kg
