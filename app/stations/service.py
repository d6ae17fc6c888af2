"""Create weighbridge stations and recognise them by their API key."""

from __future__ import annotations

import hashlib
import secrets

from sqlalchemy import select
from sqlalchemy.orm import Session

from app.errors import Conflict, InvalidInput
from app.stations.models import Station

KEY_PREFIX = "tks_"


def hash_key(key: str) -> str:
    """SHA-256 of a station key: keys carry 256 random bits, so a fast hash is safe and indexable."""
    return hashlib.sha256(key.encode()).hexdigest()


def new_key() -> str:
    """A fresh random station key (256 bits)."""
    return KEY_PREFIX + secrets.token_urlsafe(32)


def create_station(session: Session, *, name: str) -> tuple[Station, str]:
    """Store a station and return it with its key, which is shown this once and kept only as a hash."""
    name = " ".join(name.split())
    if not 1 <= len(name) <= 120:
        raise InvalidInput("name: give the station a name of 1 to 120 characters", field="name", rule="length")
    if session.scalar(select(Station.id).where(Station.name == name)) is not None:
        raise Conflict(f"name: a station named {name!r} already exists", field="name", rule="unique")
    key = new_key()
    station = Station(name=name, key_hash=hash_key(key), key_prefix=key[:10])
    session.add(station)
    session.commit()
    return station, key


def authenticate_station(session: Session, key: str) -> Station | None:
    """The active station holding this key, or None."""
    station = session.scalar(select(Station).where(Station.key_hash == hash_key(key)))
    return station if station is not None and station.active else None
