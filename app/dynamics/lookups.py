"""How this package's doors find a vehicle or an inspection, whose packages sit above it.

The composition root hands the finders in (app/composition.py); a door used before that fails
loudly rather than guess.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from sqlalchemy.orm import Session

from app.dynamics.protocols import EstimatedInspection, FiguredVehicle


class InspectionGetter(Protocol):
    """The inspection with this id (only the station's, given one), or NotFound."""

    def __call__(
        self, session: Session, inspection_id: int, *, station_id: int | None = None
    ) -> EstimatedInspection:
        """The inspection, or NotFound answered as for one that does not exist."""


VehicleFinder = Callable[[Session, str], FiguredVehicle | None]

_find_vehicle: VehicleFinder | None = None
_display_registration: Callable[[str], str] | None = None
_get_inspection: InspectionGetter | None = None


class NotWired(RuntimeError):
    """A door was used before the composition root handed this package its finders."""


def find_vehicles_with(finder: VehicleFinder, display: Callable[[str], str]) -> None:
    """Find a vehicle by its registration with `finder`, and print a registration with `display`."""
    global _find_vehicle, _display_registration
    _find_vehicle, _display_registration = finder, display


def get_inspections_with(getter: InspectionGetter) -> None:
    """Get an inspection by its id with `getter` from now on."""
    global _get_inspection
    _get_inspection = getter


def find_vehicle(session: Session, registration: str) -> FiguredVehicle | None:
    """The vehicle with this registration, or None."""
    if _find_vehicle is None:
        raise NotWired("app.dynamics finds no vehicle: import app.composition, which wires it")
    return _find_vehicle(session, registration)


def display_registration(registration: str) -> str:
    """The registration as printed."""
    if _display_registration is None:
        raise NotWired("app.dynamics prints no registration: import app.composition, which wires it")
    return _display_registration(registration)


def get_inspection(
    session: Session, inspection_id: int, *, station_id: int | None = None
) -> EstimatedInspection:
    """The inspection with this id (only that station's, given one), or NotFound."""
    if _get_inspection is None:
        raise NotWired("app.dynamics gets no inspection: import app.composition, which wires it")
    return _get_inspection(session, inspection_id, station_id=station_id)
