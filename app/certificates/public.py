"""Certificate routes outside the station API: published keys, public verify pages, officers' actions."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Response

from app.certificates.keys import published_keys
from app.certificates.officer_views import router as officer_router
from app.certificates.views import router as views_router
from app.config import get_settings
from app.web.deps import SessionDep

public_router = APIRouter()
public_router.include_router(views_router)
public_router.include_router(officer_router)


@public_router.get(
    "/.well-known/trikecert-keys.json",
    include_in_schema=False,  # a fixed, public address outside the station API
    summary="The public keys that sign certificate QR payloads (JWKS, every key ever used)",
)
def signing_keys(session: SessionDep, response: Response) -> dict[str, Any]:
    """To verify a QR payload offline, take the key whose `kid` is in the JWS header; check its signature."""
    response.headers["Cache-Control"] = "public, max-age=300"
    return published_keys(session, get_settings())
