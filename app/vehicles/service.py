"""Register and find vehicles; registration numbers are matched after normalising."""

from __future__ import annotations

import re
from collections.abc import Callable
from decimal import Decimal

from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session, joinedload

from app.dynamics.service import DynamicsFigures, check_figures, new_revision
from app.errors import Conflict, InvalidInput, NotFound
from app.stability import Rules, StabilityError, layout_named
from app.stability import Seat as StabilitySeat
from app.stability.validation import check_seat_layout, check_wheelbase
from app.text import TextRefused, check_text, checked, optional_checked, without_refused
from app.vehicles.models import Seat, Vehicle

MAKE_LENGTH = 80
MODEL_LENGTH = 80
CHASSIS_LENGTH = 64
REGISTRATION_LENGTH = 32

_SEPARATORS = re.compile(r"[\s\-]+")


def normalise_registration(registration_number: str) -> str:
    """The lookup key of a registration: upper case, no spaces or hyphens (`bdg-252qh` -> `BDG252QH`)."""
    return _SEPARATORS.sub("", registration_number).upper()


def display_registration(registration_number: str) -> str:
    """The registration as printed: upper case, single spaces (and nothing the text rule refuses)."""
    return " ".join(without_refused(registration_number).replace("-", " ").split()).upper()


def register_vehicle(
    session: Session,
    *,
    registration_number: str,
    make: str,
    model: str,
    wheelbase_m: Decimal,
    seats: list[tuple[str, Decimal]],
    model_year: int | None = None,
    chassis_number: str | None = None,
    rules: Rules | None = None,
    on_stored: Callable[[Session, Vehicle], None] | None = None,
    dynamics: DynamicsFigures | None = None,
    layout: str = "delta",
) -> Vehicle:
    """Store a new vehicle with its seat layout; a registration already on file is a conflict.

    Its figures for the estimates (`dynamics`, each optional) become the vehicle's revision 1. Its axle
    `layout` (delta, tadpole, quadricycle) is fixed for good: a vehicle with other axles is a new one.

    `on_stored(session, vehicle)` runs once the vehicle has its id, before the commit, so a caller
    can store a row of its own in the same transaction (the API's idempotency key).
    """
    rules = rules or Rules()
    registration_number = checked("registration_number", registration_number, max_length=REGISTRATION_LENGTH)
    key = normalise_registration(registration_number)
    if not valid_key(key):
        raise InvalidInput(
            "registration_number: use 2 to 16 letters and digits, like BDG 252 QH "
            "(spaces and hyphens are ignored)",
            field="registration_number",
            rule="format",
        )
    make = checked("make", make, max_length=MAKE_LENGTH)
    model = checked("model", model, max_length=MODEL_LENGTH)
    chassis_number = optional_checked("chassis_number", chassis_number, max_length=CHASSIS_LENGTH)
    if chassis_number:  # upper case can lengthen a text (ß is SS): the limit holds for what is stored
        chassis_number = checked("chassis_number", chassis_number.upper(), max_length=CHASSIS_LENGTH)
    try:
        axles = layout_named(layout)
    except StabilityError as error:
        raise InvalidInput(error.message, field=error.field, rule=error.rule) from error
    _check_layout(wheelbase_m, seats, rules)
    dynamics = dynamics or DynamicsFigures()
    check_figures(dynamics, seat_count=len(seats), front_wheels=axles.n_front)
    on_file = _registered_as(session, key)
    if on_file is not None:
        raise _duplicate(registration_number, on_file)
    vehicle = Vehicle(
        registration_number=display_registration(registration_number),
        registration_key=key,
        layout=axles.name,
        make=make,
        model=model,
        model_year=model_year,
        chassis_number=chassis_number,
        wheelbase_m=wheelbase_m,
        seats=[Seat(position=i, role=role, x_m=x_m) for i, (role, x_m) in enumerate(seats)],
    )
    session.add(vehicle)
    new_revision(session, vehicle, dynamics)
    try:
        if on_stored is not None:
            session.flush()
            on_stored(session, vehicle)
        session.commit()
    except IntegrityError as error:  # a concurrent registration of the same number won the race
        session.rollback()
        raise _duplicate(registration_number, _registered_as(session, key)) from error
    return vehicle


def valid_key(key: str) -> bool:
    """True for a lookup key a registration can have: 2 to 16 ASCII letters and digits."""
    return key.isascii() and key.isalnum() and 2 <= len(key) <= 16


def _registered_as(session: Session, key: str) -> str | None:
    """The registration on file under this lookup key, as it was registered."""
    return session.scalar(select(Vehicle.registration_number).where(Vehicle.registration_key == key))


def _duplicate(registration_number: str, on_file: str | None) -> Conflict:
    """`bdg-252qh` when BDG 252 QH is on file: the message names the vehicle on file."""
    wanted = display_registration(registration_number)
    shown = wanted if on_file in (None, wanted) else f"{wanted} (as {on_file})"
    return Conflict(
        f"registration_number: {shown} is already registered",
        field="registration_number",
        rule="unique",
    )


def _check_layout(wheelbase_m: Decimal, seats: list[tuple[str, Decimal]], rules: Rules) -> None:
    """Refuse an implausible wheelbase or a seat layout without the driver first."""
    try:
        check_wheelbase(wheelbase_m, rules)
        layout = [StabilitySeat(role, x_m) for role, x_m in seats]  # type: ignore[arg-type]
        check_seat_layout(layout, wheelbase_m, rules, prefix="seats")
    except StabilityError as error:
        message = error.message
        if not message.startswith(f"{error.field}:"):  # every API message starts with its field's path
            message = f"{error.field}: {message}"
        raise InvalidInput(message, field=error.field, rule=error.rule) from error


def lookup_key(registration_number: str) -> str | None:
    """The key a registration is looked up by; None for a text no registration can be (never sent to
    the database: PostgreSQL cannot even compare a NUL)."""
    try:
        key = normalise_registration(check_text(registration_number, max_length=REGISTRATION_LENGTH))
    except TextRefused:
        return None
    return key if valid_key(key) else None


def find_vehicle(session: Session, registration_number: str) -> Vehicle | None:
    """The vehicle with this registration (normalised), or None; a text no registration can be is None."""
    key = lookup_key(registration_number)
    if key is None:
        return None
    # The seats in the same round trip: every caller reads them.
    query = select(Vehicle).where(Vehicle.registration_key == key).options(joinedload(Vehicle.seats))
    return session.scalars(query).unique().one_or_none()


def get_vehicle(session: Session, registration_number: str) -> Vehicle:
    """The vehicle with this registration, or NotFound saying it is not registered."""
    vehicle = find_vehicle(session, registration_number)
    if vehicle is None:
        raise not_registered(registration_number)
    return vehicle


def not_registered(registration_number: str) -> NotFound:
    """404: no vehicle has this registration; register it first."""
    return NotFound(
        f"registration_number: no vehicle {display_registration(registration_number)} is registered; "
        "register it first with POST /api/v1/vehicles",
        field="registration_number",
        rule="registered",
    )
