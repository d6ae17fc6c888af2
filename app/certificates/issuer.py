"""Who issued a certificate, as the station API and the public may read it: a role and a display name.

Never an email address: an officer by display name and badge (`User.shown_as`), a station by its name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from sqlalchemy.orm import Session

from app.accounts.models import User
from app.certificates.models import Certificate
from app.stations.models import Station

Role = Literal["station", "officer", "administrator"]
ROLE_NAMES: dict[Role, str] = {
    "station": "Weighbridge station",
    "officer": "Inspection officer",
    "administrator": "Administrator",
}


@dataclass(frozen=True)
class Issuer:
    """The issuer's role and the name to show for them."""

    role: Role
    name: str


def issuer_of(session: Session, certificate: Certificate) -> Issuer:
    """A station by its name; an officer or administrator by role and by name and badge."""
    if certificate.issued_by_station_id is not None:
        station = session.get(Station, certificate.issued_by_station_id)
        return Issuer("station", station.name if station else ROLE_NAMES["station"])
    if certificate.issued_by_user_id is not None:
        user = session.get(User, certificate.issued_by_user_id)
        role: Role = "administrator" if user is not None and user.role == "admin" else "officer"
        return Issuer(role, user.shown_as() if user is not None else ROLE_NAMES[role])
    return Issuer("administrator", ROLE_NAMES["administrator"])  # `trikecert` on the server
