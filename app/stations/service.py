"""Create, edit, rotate the key of and disable weighbridge stations; recognise them by their API key."""

from __future__ import annotations

import hashlib
import secrets
from collections.abc import Sequence

from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from app.db import utcnow
from app.errors import Conflict, NotFound
from app.ids import parse_id
from app.stations.details import StationDetails, apply_details, checked_details
from app.stations.models import Station
from app.text import checked

KEY_PREFIX = "tks_"


def hash_key(key: str) -> str:
    """SHA-256 of a station key: keys carry 256 random bits, so a fast hash is safe and indexable."""
    return hashlib.sha256(key.encode()).hexdigest()


def new_key() -> str:
    """A fresh random station key (256 bits)."""
    return KEY_PREFIX + secrets.token_urlsafe(32)


NAME_LENGTH = 120


def _checked_name(session: Session, name: str, *, station_id: int | None = None) -> str:
    name = " ".join(checked("name", name, max_length=NAME_LENGTH).split())
    other = session.scalar(select(Station.id).where(Station.name == name))
    if other is not None and other != station_id:
        raise Conflict(f"name: a station named {name!r} already exists", field="name", rule="unique")
    return name


def create_station(
    session: Session, *, name: str, details: StationDetails | None = None
) -> tuple[Station, str]:
    """Store a station and return it with its key, which is shown this once and kept only as a hash."""
    name = _checked_name(session, name)
    checked = checked_details(details or StationDetails())
    key = new_key()
    station = Station(name=name, key_hash=hash_key(key), key_prefix=key[:10])
    apply_details(station, checked)
    session.add(station)
    try:
        session.commit()
    except IntegrityError as error:  # a station of the same name was stored meanwhile
        session.rollback()
        raise Conflict(
            f"name: a station named {name!r} already exists", field="name", rule="unique"
        ) from error
    return station, key


def update_station(
    session: Session, *, station: Station, details: StationDetails, name: str | None = None
) -> Station:
    """Replace a station's particulars (and its name when given); the key is left as it is."""
    checked = checked_details(details)
    if name is not None:
        station.name = _checked_name(session, name, station_id=station.id)
    apply_details(station, checked)
    session.commit()
    return station


def rotate_key(session: Session, *, station: Station) -> str:
    """Give the station a new key and return it (shown once); the old key stops working at once."""
    key = new_key()
    station.key_hash = hash_key(key)
    station.key_prefix = key[:10]
    station.key_rotated_at = utcnow()
    session.commit()
    return key


def set_station_active(session: Session, *, station: Station, active: bool) -> Station:
    """Enable or disable a station; a disabled station's key is refused (401) until it is enabled."""
    station.active = active
    session.commit()
    return station


def get_station(session: Session, station_id: int) -> Station:
    """The station with this id, or NotFound."""
    station = session.get(Station, station_id)
    if station is None:
        raise NotFound(f"station: station {station_id} does not exist", field="station", rule="exists")
    return station


def find_station(session: Session, name_or_id: str) -> Station:
    """The station with this name (spaces tidied) or, failing that, this id; or NotFound."""
    name = " ".join(checked("station", name_or_id, max_length=NAME_LENGTH).split())
    station = session.scalar(select(Station).where(Station.name == name))
    if station is None and (station_id := parse_id(name)) is not None:
        station = session.get(Station, station_id)
    if station is None:
        raise NotFound(f"station: no station is named {name!r}", field="station", rule="exists")
    return station


def list_stations(session: Session) -> Sequence[Station]:
    """Every station, by name."""
    return session.scalars(select(Station).order_by(Station.name)).all()


def authenticate_station(session: Session, key: str) -> Station | None:
    """The active station holding this key, or None."""
    station = session.scalar(select(Station).where(Station.key_hash == hash_key(key)))
    return station if station is not None and station.active else None
