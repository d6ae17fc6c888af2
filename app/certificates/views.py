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
from app.config import get_settings
from app.text import without_refused
from app.web.deps import SessionDep
from app.web.forms import FormErrors, query_text
from app.web.templating import render

router = APIRouter(include_in_schema=False)

HEADLINES = {"issued": "VALID", "expired": "EXPIRED", "revoked": "REVOKED", "superseded": "SUPERSEDED"}
NUMBER_HINT = "Enter the certificate number as printed, like TRK-2026-000123-K."


@router.get("/verify")
def verify_form(request: Request, number: Annotated[str | None, Query(max_length=60)] = None) -> Response:
    """Ask for a certificate number; a well-formed one goes to its page."""
    errors: dict[str, str] = {}
    if number is not None:
        refused = FormErrors()  # the text rule of every door, before the number's own shape
        number = query_text(number, "number", refused, limit=60) or without_refused(number)
        errors.update(refused.messages)
    if number is not None and not errors:
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
    """The certificate's status in large letters, the vehicle and the verdict; 404 for an unknown number."""
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
