"""The PDF as an HTTP answer: the stored bytes while the document is in force, stamped once it is not.

A revoked, superseded or expired document downloads as the stored original with a stamp across
every page (app/certificates/stamp.py), never as the clean paper; the response says so in its file name
and headers. Every answer has an ETag, and a repeat whose copy is current gets 304.
"""

from __future__ import annotations

from sqlalchemy.orm import Session
from starlette.responses import Response

from app.certificates.models import Certificate
from app.certificates.records import certificate_pdf, certificate_status, verify_base
from app.certificates.wording import public_status
from app.config import get_settings

# certified, refused (in force), revoked, superseded or expired: what the paper shows, in the words
# of the JSON verification's `status` (a refusal is never "issued" or "valid" to a machine either).
STATUS_HEADER = "X-Document-Status"
ORIGINAL_HEADER = "X-Original-SHA256"  # the stored original's hash, as the record has it


def etag_matches(if_none_match: str | None, etag: str) -> bool:
    """True when an If-None-Match header names this ETag (weak comparison) or is '*'."""
    if not if_none_match:
        return False
    tags = [tag.strip().removeprefix("W/") for tag in if_none_match.split(",")]
    return "*" in tags or etag in tags


def pdf_filename(number: str, status: str) -> str:
    """The download's file name: the number, and the status when it is no longer in force."""
    return f"{number}.pdf" if status == "issued" else f"{number}-{status.upper()}.pdf"


def pdf_response(session: Session, certificate: Certificate, if_none_match: str | None) -> Response:
    """200 with the PDF (stamped unless in force), or 304 when the client's copy is current.

    In force, the ETag is the SHA-256 of the stored bytes; stamped, a hash of that and the stamp's
    words, so a copy fetched before the revocation is never answered 304.
    """
    # The PDF library is loaded by the first paper a process serves, not by every process that starts.
    from app.certificates.stamp import stamp_of, stamped_pdf

    status = certificate_status(certificate)
    stamp = stamp_of(certificate, status, verify_base(get_settings()))
    tag = certificate.pdf_sha256 if stamp is None else stamp.etag(certificate.pdf_sha256)
    etag = f'"{tag}"'
    headers = {
        "ETag": etag,
        "Cache-Control": "private, no-cache",
        STATUS_HEADER: public_status(certificate.kind, status),
        ORIGINAL_HEADER: certificate.pdf_sha256,
    }
    if etag_matches(if_none_match, etag):
        return Response(status_code=304, headers=headers)
    headers["Content-Disposition"] = f'inline; filename="{pdf_filename(certificate.number, status)}"'
    stored = certificate_pdf(session, certificate)
    body = stored if stamp is None else stamped_pdf(stored, stamp)
    return Response(body, media_type="application/pdf", headers=headers)
