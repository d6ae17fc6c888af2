"""The service's request from the API's body: readings, occupants and the estimates' inputs."""

from __future__ import annotations

from app.dynamics.estimates import CgLift
from app.inspections.schemas import InspectionIn, ReadingsIn
from app.inspections.service import InspectionRequest
from app.stability import LoadItem, MeasuredCase, Seat, WheelReadings
from app.stability.layout import ALL_WHEELS, OVERALL


def wheel_readings(body: ReadingsIn) -> WheelReadings:
    """The core's readings from the API's."""
    return WheelReadings(**{wheel: tuple(getattr(body, wheel) or ()) for wheel in (*ALL_WHEELS, OVERALL)})


def inspection_request(body: InspectionIn) -> InspectionRequest:
    """The service's request from the API body."""
    occupants = body.occupants
    return InspectionRequest(
        registration_number=body.registration_number,
        readings=wheel_readings(body.readings),
        wheelbase_m=body.wheelbase_m,
        occupant_mass_kg=occupants.mass_kg if occupants else None,
        seats=tuple(Seat(s.role, s.x_m) for s in occupants.seats) if occupants and occupants.seats else None,
        load_items=tuple(LoadItem(i.mass_kg, i.x_m, i.label) for i in body.load_items),
        measured_cases=tuple(
            MeasuredCase(m.occupants, wheel_readings(m.readings)) for m in body.measured_cases
        ),
        cg_lift=CgLift(body.cg_lift.lift_height_m, tuple(body.cg_lift.front_kg)) if body.cg_lift else None,
        cg_height_m=body.cg_height_m,
    )
