"""Who acts on certificates, as the audit log names them, and the refusal when they may not."""

from __future__ import annotations

import getpass
from dataclasses import dataclass

from app.accounts.models import User
from app.errors import ServiceError
from app.stations.models import Station


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

    @classmethod
    def of_station(cls, station: Station) -> Actor:
        """A weighbridge station, through the API."""
        return cls(label=f"station:{station.id}:{station.name}"[:200], station_id=station.id)

    @classmethod
    def of_user(cls, user: User) -> Actor:
        """An officer or admin, through the pages."""
        return cls(label=f"user:{user.id}:{user.email}"[:200], user_id=user.id, admin=user.role == "admin")

    @classmethod
    def of_cli(cls) -> Actor:
        """Whoever runs the `trikecert` command on the server (an administrator)."""
        return cls(label=f"cli:{getpass.getuser()}"[:200], admin=True)
