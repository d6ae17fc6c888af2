"""Station API for certificates: issue one for an inspection, read it, download its PDF."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Header, Path, Response, status

from app.api.errors import error_responses
from app.certificates.actors import Actor
from app.certificates.models import Certificate
from app.certificates.pdf_response import pdf_response
from app.certificates.records import certificate_facts, certificate_status, get_certificate, verify_base
from app.certificates.schemas import CertificateOut, RevocationOut
from app.certificates.service import issue_certificate
from app.config import get_settings
from app.ids import InspectionId
from app.stations.deps import SessionDep, StationDep

router = APIRouter(tags=["certificates"])
NumberPath = Annotated[
    str,
    Path(
        max_length=40,
        description="The certificate number, e.g. TRK-2026-000001-A (case and hyphens forgiven).",
    ),
]


def certificate_out(certificate: Certificate) -> CertificateOut:
    """The API view of a certificate, with its status as of now."""
    facts = certificate_facts(certificate)
    verify = f"{verify_base(get_settings())}/{certificate.number}"
    revocation = certificate.revocation
    return CertificateOut(
        number=certificate.number,
        kind="compliant" if certificate.kind == "compliant" else "refusal",
        status=certificate_status(certificate),
        registration_number=certificate.registration_number,
        inspection_id=certificate.inspection_id,
        compliant=certificate.compliant,
        max_compliant_occupants=certificate.max_compliant_occupants,
        max_occupancy=facts.occupancy,
        verdict=facts.verdict,
        issued_at=certificate.issued_at,
        expires_at=certificate.expires_at,
        issued_by=certificate.issued_by,
        supersedes=certificate.supersedes.number if certificate.supersedes else None,
        superseded_by=certificate.superseded_by.number if certificate.superseded_by else None,
        revocation=RevocationOut(revoked_at=revocation.revoked_at, reason=revocation.reason)
        if revocation
        else None,
        key_id=certificate.key_id,
        qr_payload=certificate.qr_payload,
        verify_url=verify,
        qr_url=f"{verify}?p={certificate.qr_payload}",
        pdf_url=f"/api/v1/certificates/{certificate.number}/pdf",
        pdf_sha256=certificate.pdf_sha256,
    )


@router.post(
    "/inspections/{inspection_id}/certificate",
    status_code=status.HTTP_201_CREATED,
    response_model=CertificateOut,
    responses={
        200: {"model": CertificateOut, "description": "The inspection already has this current certificate."},
        **error_responses(401, 404, 409, 422),
    },
    summary="Issue the certificate (or refusal) of one of this station's inspections",
)
def create_certificate(
    inspection_id: InspectionId, session: SessionDep, station: StationDep, response: Response
) -> CertificateOut:
    """201 with a new certificate; 200 with the current one if the inspection is already certified.

    A compliant inspection gets a certificate, a non-compliant one a refusal. It supersedes the
    vehicle's previous certificate. 409 when a newer inspection of the vehicle is already certified
    or this inspection's certificate was revoked or has expired.
    """
    issued = issue_certificate(
        session, inspection_id=inspection_id, actor=Actor.of_station(station), settings=get_settings()
    )
    number = issued.certificate.number
    response.status_code = status.HTTP_201_CREATED if issued.created else status.HTTP_200_OK
    response.headers["Location"] = f"/api/v1/certificates/{number}"
    return certificate_out(issued.certificate)


@router.get(
    "/certificates/{number}",
    response_model=CertificateOut,
    responses=error_responses(401, 404, 422),
    summary="Read a certificate with its current status",
)
def read_certificate(number: NumberPath, session: SessionDep, _station: StationDep) -> CertificateOut:
    """The certificate; `status` is computed now (issued, revoked, superseded or expired)."""
    return certificate_out(get_certificate(session, number))


@router.get(
    "/certificates/{number}/pdf",
    response_class=Response,
    responses={
        200: {"content": {"application/pdf": {}}, "description": "The PDF, byte for byte as issued."},
        304: {"description": "Not modified: the ETag given in If-None-Match still matches."},
        **error_responses(401, 404, 422),
    },
    summary="Download the certificate's PDF (the same bytes every time; ETag and If-None-Match)",
)
def read_certificate_pdf(
    number: NumberPath,
    session: SessionDep,
    _station: StationDep,
    if_none_match: Annotated[str | None, Header(max_length=1000)] = None,
) -> Response:
    """The PDF rendered at issue; its ETag is the SHA-256 of the bytes."""
    return pdf_response(session, get_certificate(session, number), if_none_match)
