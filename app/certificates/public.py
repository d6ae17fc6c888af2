"""Certificate routes outside the station API: published keys, public verify pages, officers' actions."""

from __future__ import annotations

from typing import Annotated, Any
from urllib.parse import quote, unquote

from fastapi import APIRouter, Path, Response
from starlette.requests import Request
from starlette.responses import RedirectResponse

from app.certificates.bundle_answer import bundle_response
from app.certificates.officer_views import router as officer_router
from app.certificates.records import verify_base
from app.certificates.trust_bundle import served_bundle
from app.certificates.verify_json import error_json, number_of_payload, wants_json
from app.certificates.views import router as views_router
from app.config import get_settings
from app.errors import InvalidInput
from app.trust.keys import published_keys
from app.web.deps import SessionDep
from app.web.templating import render

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


@public_router.get(
    "/.well-known/trikecert-trust",
    include_in_schema=False,  # a fixed, public address outside the station API
    summary="The trust bundle: keys, periods, revoked numbers, signed (JWS); for offline checks",
)
def trust_bundle(request: Request, session: SessionDep) -> Response:
    """The signed trust bundle (docs/verification.md): 304 when If-None-Match names it; gzip when asked."""
    built = served_bundle(session, get_settings())
    return bundle_response(
        built, request.headers.get("accept-encoding", ""), request.headers.get("if-none-match")
    )


def _raw_payload(request: Request) -> str | None:
    """The payload from the path as sent, percent-decoded exactly once (a '%25' in it stays '%')."""
    raw = request.scope.get("raw_path")
    if not isinstance(raw, bytes):
        return None
    path = raw.decode("latin-1").split("?", 1)[0]
    marker = max(path.find("/V/"), path.find("/v/"))
    return unquote(path[marker + 3 :]) if marker >= 0 else None


@public_router.get("/V/{payload:path}", include_in_schema=False)
@public_router.get("/v/{payload:path}", include_in_schema=False)
def short_verify(
    request: Request, session: SessionDep, payload: Annotated[str, Path(max_length=2000)]
) -> Response:
    """What a certificate's QR code opens: the verify page of the number its payload names, checking it.

    303 to /verify/{number}?p=<payload> (JSON clients follow it to the JSON verification). A payload
    no number can be read from is 422: the form to type the number, or the API's error body.
    """
    payload = _raw_payload(request) or payload
    try:
        number = number_of_payload(session, payload)
    except InvalidInput as refused:  # nothing to show but the form
        if wants_json(request):
            return error_json(refused)
        return render(
            request,
            "certificates/verify_form.html",
            {
                "errors": {
                    "number": "The QR code is not a certificate's code, or it is damaged. "
                    "Type the certificate number printed on the paper."
                },
                "values": {"number": ""},
                "verify_url": verify_base(get_settings()),
            },
            status_code=422,
        )
    return RedirectResponse(f"/verify/{number}?p={quote(payload, safe='')}", status_code=303)
