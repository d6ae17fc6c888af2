"""Who acts on certificates: as the audit log names them, as documents and officers' pages name them
(by name and badge, never by email), and the refusal when they may not."""

from __future__ import annotations

import getpass
from dataclasses import dataclass

from sqlalchemy.orm import Session

from app.accounts.models import User
from app.accounts.names import person_on_page
from app.errors import ServiceError
from app.i18n.active import N_, gettext
from app.inspections.models import Inspection
from app.stations.models import Station
from app.web.formatting import NOT_RECORDED, not_recorded

# English on a document's frozen facts (the binding text); translated where a page shows who acted.
COMMAND_LINE = N_("an administrator at the server (command line)")


class Forbidden(ServiceError):
    """The actor may not do this (403)."""

    status = 403


@dataclass(frozen=True)
class Actor:
    """Who acts, as written in the audit log: a station, a signed-in user, or the command line."""

    label: str
    station_id: int | None = None
    user_id: int | None = None
    admin: bool = False
    shown_as: str = NOT_RECORDED  # as a document names who issued it

    @classmethod
    def of_station(cls, station: Station) -> Actor:
        """A weighbridge station, through the API."""
        return cls(
            label=f"station:{station.id}:{station.name}"[:200],
            station_id=station.id,
            shown_as=station_shown_as(station),
        )

    @classmethod
    def of_user(cls, user: User) -> Actor:
        """An officer or admin, through the pages."""
        return cls(
            label=f"user:{user.id}:{user.email}"[:200],
            user_id=user.id,
            admin=user.role == "admin",
            shown_as=user.shown_as(),
        )

    @classmethod
    def of_cli(cls) -> Actor:
        """Whoever runs the `trikecert` command on the server (an administrator)."""
        return cls(label=f"cli:{getpass.getuser()}"[:200], admin=True, shown_as=COMMAND_LINE)


def station_shown_as(station: Station | str) -> str:
    """A station (or its name) as documents name it when it acted by itself: 'Ikeja weighbridge, weighbridge
    station' (a comma, as a name may end in brackets of its own: 'Demo weighbridge (Agbara)')."""
    return f"{station if isinstance(station, str) else station.name}, weighbridge station"


def _station_on_page(station: Station) -> str:
    """A station as a page names it, in the page's language: 'Ikeja weighbridge, weighbridge station'."""
    return gettext("%(name)s, weighbridge station") % {"name": station.name}


def officer_of(session: Session, inspection: Inspection) -> User | None:
    """The officer who recorded the weighing, if one did."""
    return session.get(User, inspection.user_id) if inspection.user_id is not None else None


def recorded_by(session: Session, inspection: Inspection) -> str:
    """Who recorded a weighing, on a page: the officer by name and badge, else the station that
    submitted it (in the page's language)."""
    officer = officer_of(session, inspection)
    if officer is not None:
        return person_on_page(officer)
    if inspection.station is not None:
        return _station_on_page(inspection.station)
    return not_recorded()


def issued_by(session: Session, *, user_id: int | None, station_id: int | None, label: str) -> str:
    """Who issued a document, on a page, from what its row keeps (the issuer's ids and audit label)."""
    if user_id is not None and (user := session.get(User, user_id)) is not None:
        return person_on_page(user)
    if station_id is not None and (station := session.get(Station, station_id)) is not None:
        return _station_on_page(station)
    return gettext(COMMAND_LINE) if label.startswith("cli:") else not_recorded()
