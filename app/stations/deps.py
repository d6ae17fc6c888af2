"""The API's authentication: every call carries `Authorization: Bearer <station key>`, counted per key."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, HTTPException, status
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer
from sqlalchemy.orm import Session

from app.audit.recorder import Actor, act_as
from app.config import get_settings
from app.db import get_session
from app.stations.models import Station
from app.stations.rate_limit import RateLimit, authenticate_and_count

bearer = HTTPBearer(auto_error=False, description="The station's API key, from `trikecert create-station`.")
SessionDep = Annotated[Session, Depends(get_session)]


def current_station(
    session: SessionDep,
    credentials: Annotated[HTTPAuthorizationCredentials | None, Depends(bearer)],
) -> Station:
    """The station whose key signs this request; 401 when the key is missing, unknown or disabled.

    Every authenticated request counts against the station key's rate limit (429 beyond it).
    """
    if credentials is None or credentials.scheme.lower() != "bearer":
        raise HTTPException(
            status.HTTP_401_UNAUTHORIZED,
            "Authorization: send the station key as `Authorization: Bearer <key>`",
            headers={"WWW-Authenticate": "Bearer"},
        )
    settings = get_settings()
    limit = RateLimit(settings.station_rate_limit, settings.station_rate_window_seconds)
    station = authenticate_and_count(session, credentials.credentials, limit=limit)
    if station is None:
        raise HTTPException(
            status.HTTP_401_UNAUTHORIZED,
            "Authorization: the station key is not recognised or the station is disabled",
            headers={"WWW-Authenticate": 'Bearer error="invalid_token"'},
        )
    act_as(session, Actor("station", station.id, station.name))
    return station


StationDep = Annotated[Station, Depends(current_station)]
