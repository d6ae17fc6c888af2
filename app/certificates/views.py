"""The public verification pages: no sign-in, no JavaScript; anyone can check a certificate number."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any

from fastapi import APIRouter, Path, Query
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app import wording
from app.certificates.answer_cache import kept_answer, verdict_until
from app.certificates.models import Certificate
from app.certificates.records import certificate_facts, certificate_status, get_certificate, verify_base
from app.certificates.verification import PayloadCheck, check_payload
from app.certificates.verify_json import payload_param, verification_json, wants_json
from app.certificates.wording import (
    NumberRule,
    lapsed_sentence,
    number_headline,
    public_status,
    qr_explanation,
    qr_title,
    qr_tone,
    sentence,
    until_sentence,
)
from app.config import get_settings
from app.errors import NotFound
from app.text import without_refused
from app.trust.keys import published_keys
from app.trust.numbers import InvalidNumber, parse_number
from app.web.deps import SessionDep
from app.web.formatting import long_date
from app.web.forms import FormErrors, query_text
from app.web.templating import render

router = APIRouter(include_in_schema=False)

NUMBER_HINT = "Enter the certificate number as printed, like TRK-2026-000123-K."


def status_since(certificate: Certificate, status: str) -> str | None:
    """The date a document stopped counting (revoked, replaced, expired), as printed."""
    if status == "revoked" and certificate.revocation is not None:
        return long_date(certificate.revocation.revoked_at)
    if status == "superseded" and certificate.superseded_by is not None:
        return long_date(certificate.superseded_by.issued_at)
    if status == "expired":
        return long_date(certificate.expires_at)
    return None


def document_context(certificate: Certificate, payload: PayloadCheck | None = None) -> dict[str, Any]:
    """What verify.html shows: the banner (headline, tone, dates), the QR check and the frozen facts."""
    status = certificate_status(certificate)
    facts = certificate_facts(certificate)
    kind = certificate.kind
    newer = certificate.superseded_by
    public = public_status(kind, status)
    genuine = payload is not None and payload.genuine
    return {
        "certificate": certificate,
        "facts": facts,
        "rows": facts.cases,
        "status": status,
        "kind_word": wording.document_kind(kind),
        "title_text": wording.document_title(kind),
        "headline": wording.status_headline_on(kind, status, status_since(certificate, status)),
        "tone": wording.status_tone(kind, status),
        "valid_until": long_date(certificate.expires_at),
        "until_text": until_sentence(kind, long_date(certificate.expires_at)),
        "lapsed_text": lapsed_sentence(kind, status),
        "issued_on": long_date(certificate.issued_at),
        "newer_word": wording.document_kind(newer.kind) if newer is not None else None,
        "public_status": public,
        "payload": payload,
        "qr_tone": qr_tone(public, genuine),
        "qr_title": qr_title(kind, public, genuine),
        "qr_explanation": qr_explanation(public),
        "qr_reason": wording.qr_reason(payload.reason) if payload is not None else None,
    }


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
        except InvalidNumber as error:  # the words the page of that number and the API give
            errors["number"] = sentence(str(error)) if number.strip() else NUMBER_HINT
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
    """One banner with the status, the registration and the occupancy; the QR check; then the details.

    With `Accept: application/json`, the public JSON verification instead (as /api/v1/verify/{number}).
    """
    p = payload_param(request) if p is not None else None
    if wants_json(request):
        return verification_json(session, number, p)
    if p:
        return _verify_page(request, session, number, p)[0]
    return kept_answer("verify-html", number, lambda: _verify_page(request, session, number, None))


def _verify_page(
    request: Request, session: SessionDep, number: str, p: str | None
) -> tuple[Response, datetime | None]:
    try:
        certificate = get_certificate(session, number)
    except NotFound as missing:
        return not_found_page(request, number, missing), None
    payload = check_payload(p, published_keys(session, get_settings()), certificate) if p else None
    page = render(request, "certificates/verify.html", document_context(certificate, payload))
    return page, verdict_until(certificate)


def not_found_page(request: Request, number: str, missing: NotFound) -> Response:
    """404 under a red banner: the number finds no document, in the words of the form and the API."""
    problem = missing.problems[0]
    rules: dict[str, NumberRule] = {"format": "format", "check_letter": "check_letter"}
    rule = rules.get(problem.rule, "exists")
    message = sentence(problem.message.removeprefix("number: "))
    return render(
        request,
        "certificates/not_found.html",
        {
            "number": number,
            "rule": rule,
            "headline": number_headline(rule),
            "message": message,
            "errors": {"number": message},
            "values": {"number": number},
        },
        status_code=404,
    )
