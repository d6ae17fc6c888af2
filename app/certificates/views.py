"""The public verification pages: no sign-in, no JavaScript; anyone can check a certificate number."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, Query
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.certificates.keys import published_keys
from app.certificates.numbers import InvalidNumber, parse_number
from app.certificates.records import certificate_facts, certificate_status, find_certificate, verify_base
from app.certificates.verification import check_payload
from app.certificates.verify_json import payload_param, verification_json, wants_json
from app.config import get_settings
from app.web.deps import SessionDep
from app.web.templating import render

router = APIRouter(include_in_schema=False)

HEADLINES = {"issued": "VALID", "expired": "EXPIRED", "revoked": "REVOKED", "superseded": "SUPERSEDED"}
NUMBER_HINT = "Enter the certificate number as printed, like TRK-2026-000123-K."


@router.get("/verify")
def verify_form(request: Request, number: Annotated[str | None, Query(max_length=60)] = None) -> Response:
    """Ask for a certificate number; a well-formed one goes to its page."""
    errors: dict[str, str] = {}
    if number is not None:
        try:
            return RedirectResponse(f"/verify/{parse_number(number)}", status_code=303)
        except InvalidNumber:
            errors["number"] = (
                f"{NUMBER_HINT} Check each character: the last letter does not match the others"
                if number.strip()
                else NUMBER_HINT
            )
    return render(
        request,
        "certificates/verify_form.html",
        {"errors": errors, "values": {"number": number or ""}, "verify_url": verify_base(get_settings())},
        status_code=422 if errors else 200,
    )


@router.get("/verify/{number}")
def verify_page(
    request: Request,
    session: SessionDep,
    number: Annotated[str, Path(max_length=60)],
    p: Annotated[
        str | None, Query(max_length=2000, description="The signed payload from the QR code.")
    ] = None,
) -> Response:
    """The certificate's status in large letters, the vehicle and the verdict; 404 for an unknown number.

    With `Accept: application/json`, the public JSON verification instead (as /api/v1/verify/{number}).
    """
    p = payload_param(request) if p is not None else None
    if wants_json(request):
        return verification_json(session, number, p)
    certificate = find_certificate(session, number)
    if certificate is None:
        return render(request, "certificates/not_found.html", {"number": number}, status_code=404)
    status = certificate_status(certificate)
    payload = check_payload(p, published_keys(session, get_settings()), certificate) if p else None
    return render(
        request,
        "certificates/verify.html",
        {
            "certificate": certificate,
            "facts": certificate_facts(certificate),
            "status": status,
            "headline": HEADLINES[status],
            "payload": payload,
            "rows": certificate_facts(certificate).cases,
        },
    )
