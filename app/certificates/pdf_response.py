"""The stored PDF as an HTTP answer: the same bytes every time, an ETag, and 304 for a repeat."""

from __future__ import annotations

from sqlalchemy.orm import Session
from starlette.responses import Response

from app.certificates.models import Certificate
from app.certificates.records import certificate_pdf


def etag_matches(if_none_match: str | None, etag: str) -> bool:
    """True when an If-None-Match header names this ETag (weak comparison) or is '*'."""
    if not if_none_match:
        return False
    tags = [tag.strip().removeprefix("W/") for tag in if_none_match.split(",")]
    return "*" in tags or etag in tags


def pdf_response(session: Session, certificate: Certificate, if_none_match: str | None) -> Response:
    """200 with the PDF rendered at issue, or 304 when the client's copy is current; ETag = SHA-256."""
    etag = f'"{certificate.pdf_sha256}"'
    headers = {"ETag": etag, "Cache-Control": "private, no-cache"}
    if etag_matches(if_none_match, etag):
        return Response(status_code=304, headers=headers)
    headers["Content-Disposition"] = f'inline; filename="{certificate.number}.pdf"'
    return Response(certificate_pdf(session, certificate), media_type="application/pdf", headers=headers)
