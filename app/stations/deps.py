"""The API's authentication: every call carries `Authorization: Bearer <station key>`, counted per key."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Header, HTTPException, Request, status
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer
from fastapi.security.utils import get_authorization_scheme_param
from sqlalchemy.orm import Session
from starlette.types import Scope

from app.api.address_limits import client_address, windows
from app.api.windows import RateLimit
from app.audit.recorder import Actor, act_as
from app.config import get_settings
from app.db import get_session
from app.errors import ServiceError
from app.stations.models import Station
from app.stations.rate_limit import RATE_LIMIT_RULE, authenticate_and_count

BEARER_SCHEME = "HTTPBearer"  # the security scheme's name in OpenAPI
bearer = HTTPBearer(
    auto_error=False,
    scheme_name=BEARER_SCHEME,
    description="The station's API key, from `trikecert create-station`.",
)
SessionDep = Annotated[Session, Depends(get_session)]


def bearer_key(authorization: str | None) -> str:
    """The station key of an `Authorization: Bearer <key>` header; 401 when there is none (the key is
    checked against the stations later)."""
    scheme, key = get_authorization_scheme_param(authorization)
    if not key or scheme.lower() != "bearer":
        raise HTTPException(
            status.HTTP_401_UNAUTHORIZED,
            "Authorization: send the station key as `Authorization: Bearer <key>`",
            headers={"WWW-Authenticate": "Bearer"},
        )
    return key


def station_key(credentials: Annotated[HTTPAuthorizationCredentials | None, Depends(bearer)]) -> str:
    """The key a request is signed with (the security scheme in OpenAPI); 401 when there is none."""
    return bearer_key(f"{credentials.scheme} {credentials.credentials}" if credentials else None)


StationKey = Annotated[str, Depends(station_key)]
# The raw header, read without the security dependency's cost (the hot path declares the scheme in
# its OpenAPI entry instead): hand it to `bearer_key`.
AuthorizationHeader = Annotated[str | None, Header(alias="Authorization", include_in_schema=False)]


def unknown_key() -> HTTPException:
    """401 for a key no active station holds."""
    return HTTPException(
        status.HTTP_401_UNAUTHORIZED,
        "Authorization: the station key is not recognised or the station is disabled",
        headers={"WWW-Authenticate": 'Bearer error="invalid_token"'},
    )


class BadKeysLimited(ServiceError):
    """Too many keys no station holds, from one address in this window (429, with Retry-After)."""

    status = 429

    def __init__(self, limit: RateLimit, retry_after: int) -> None:
        super().__init__(
            f"Authorization: more than {limit.limit} requests with a key no station holds came from "
            f"this address in {limit.window_seconds} s; retry after {retry_after} s",
            field="Authorization",
            rule=RATE_LIMIT_RULE,
        )
        self.retry_after = retry_after
        self.headers = {"Retry-After": str(retry_after)}


def refused_key(scope: Scope) -> Exception:
    """401 for a key no active station holds, counted against its address; beyond the address's
    limit of such keys, 429 with Retry-After instead.

    Only refused keys are counted, and a valid key is never refused for its address: a station
    behind the same carrier-grade NAT as whoever sends bad keys keeps working (docs/deployment.md).
    """
    settings = get_settings()
    limit = RateLimit(settings.bad_key_limit, settings.bad_key_window_seconds)
    retry_after = windows(scope, "bad_key", limit).count(client_address(scope))
    return unknown_key() if retry_after is None else BadKeysLimited(limit, retry_after)


def current_station(request: Request, session: SessionDep, key: StationKey) -> Station:
    """The station whose key signs this request; 401 when the key is missing, unknown or disabled
    (429 once its address sent too many unknown keys).

    Every authenticated request counts against the station key's rate limit (429 beyond it).
    """
    settings = get_settings()
    limit = RateLimit(settings.station_rate_limit, settings.station_rate_window_seconds)
    station = authenticate_and_count(session, key, limit=limit)
    if station is None:
        raise refused_key(request.scope)
    act_as(session, Actor("station", station.id, station.name))
    return station


StationDep = Annotated[Station, Depends(current_station)]
