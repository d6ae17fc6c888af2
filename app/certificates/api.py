"""Station API for certificates: issue one for an inspection, read it, download its PDF; and the
public JSON verification, which needs no key.

A station reads only the certificates of inspections it submitted: another station's is answered
exactly as one that does not exist, as inspections are.
"""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Header, Path, Query, Request, Response, status
from sqlalchemy.orm import Session

from app.api.errors import error_responses
from app.api.ids import InspectionId
from app.certificates.actors import Actor
from app.certificates.issuer import issuer_of
from app.certificates.models import Certificate
from app.certificates.pdf_response import pdf_response
from app.certificates.records import certificate_facts, certificate_status, get_certificate, verify_base
from app.certificates.schemas import CertificateOut, IssuerOut, RevocationOut, VerificationOut
from app.certificates.service import issue_certificate
from app.certificates.verification_examples import VERIFICATION_EXAMPLES
from app.certificates.verify_json import api_verification, payload_param
from app.certificates.wording import in_force, not_on_record, public_status
from app.config import get_settings
from app.errors import NotFound
from app.inspections.models import Inspection
from app.stations.deps import SessionDep, StationDep
from app.stations.models import Station
from app.trust.numbers import parse_number
from app.trust.signing import qr_url_of

router = APIRouter(tags=["certificates"])
NumberPath = Annotated[
    str,
    Path(
        max_length=40,
        description="The certificate number, e.g. TRK-2026-000001-E (case and hyphens forgiven).",
    ),
]


def station_certificate(session: Session, number: str, station: Station) -> Certificate:
    """The certificate with this number if the station submitted its inspection; else NotFound, as unknown."""
    certificate = get_certificate(session, number)
    inspection = session.get(Inspection, certificate.inspection_id)
    if inspection is None or inspection.station_id != station.id:
        raise NotFound(f"number: {not_on_record(str(parse_number(number)))}", field="number", rule="exists")
    return certificate


def certificate_out(session: Session, certificate: Certificate) -> CertificateOut:
    """The API view of a certificate, with its status as of now."""
    facts = certificate_facts(certificate)
    settings = get_settings()
    verify = f"{verify_base(settings)}/{certificate.number}"
    issuer = issuer_of(session, certificate)
    revocation = certificate.revocation
    status = certificate_status(certificate)
    meaning = public_status(certificate.kind, status)
    return CertificateOut(
        number=certificate.number,
        kind="compliant" if certificate.kind == "compliant" else "refusal",
        status=status,
        document_status=meaning,
        in_force=in_force(meaning),
        registration_number=certificate.registration_number,
        inspection_id=certificate.inspection_id,
        compliant=certificate.compliant,
        max_compliant_occupants=certificate.max_compliant_occupants,
        max_occupancy=facts.occupancy,
        verdict=facts.verdict,
        issued_at=certificate.issued_at,
        expires_at=certificate.expires_at,
        issued_by=IssuerOut(role=issuer.role, name=issuer.name),
        supersedes=certificate.supersedes.number if certificate.supersedes else None,
        superseded_by=certificate.superseded_by.number if certificate.superseded_by else None,
        revocation=RevocationOut(revoked_at=revocation.revoked_at, reason=revocation.reason)
        if revocation
        else None,
        key_id=certificate.key_id,
        qr_payload=certificate.qr_payload,
        verify_url=verify,
        qr_url=qr_url_of(settings.base_url, certificate.number, certificate.qr_payload),
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
    inspection_id: InspectionId,
    session: SessionDep,
    station: StationDep,
    response: Response,
    second_language: Annotated[
        Literal["en", "ha", "yo", "ig", "pcm"] | None,
        Query(
            description="The language printed under the English on the paper: ha (Hausa), yo (Yoruba), "
            "ig (Igbo), pcm (Nigerian Pidgin), or en for English only; absent: the service's setting "
            "(TRIKECERT_PAPER_SECOND_LANGUAGE). The English text stays the legally binding one, and the "
            "signed QR payload is the same in every language. An inspection already certified keeps its "
            "paper as issued.",
            examples=["ha"],
        ),
    ] = None,
) -> CertificateOut:
    """201 with a new certificate; 200 with the current one if the inspection is already certified.

    A compliant inspection gets a certificate, a non-compliant one a refusal. It supersedes the
    vehicle's previous certificate. 409 when a newer inspection of the vehicle is already certified
    or this inspection's certificate was revoked or has expired. `?second_language=ha` prints the paper
    in English and Hausa (or yo, ig, pcm; en: English only).
    """
    issued = issue_certificate(
        session,
        inspection_id=inspection_id,
        actor=Actor.of_station(station),
        settings=get_settings(),
        second_language=second_language,
    )
    number = issued.certificate.number
    response.status_code = status.HTTP_201_CREATED if issued.created else status.HTTP_200_OK
    response.headers["Location"] = f"/api/v1/certificates/{number}"
    return certificate_out(session, issued.certificate)


@router.get(
    "/certificates/{number}",
    response_model=CertificateOut,
    responses=error_responses(401, 404, 422),
    summary="Read one of this station's certificates with its current status",
)
def read_certificate(number: NumberPath, session: SessionDep, station: StationDep) -> CertificateOut:
    """The certificate; `status` is computed now (issued, revoked, superseded or expired).

    404 for a certificate of another station's inspection, as for one that does not exist.
    """
    return certificate_out(session, station_certificate(session, number, station))


@router.get(
    "/certificates/{number}/pdf",
    response_class=Response,
    responses={
        200: {
            "content": {"application/pdf": {}},
            "description": "The PDF: byte for byte as issued while in force; once revoked, superseded "
            "or expired, the stored original with a stamp across every page (an incremental update: "
            "the file still begins with the original bytes, whose SHA-256 is `X-Original-SHA256`).",
            "headers": {
                "X-Document-Status": {
                    "description": "What the paper shows: certified or refused (in force), or revoked, "
                    "superseded or expired (stamped so)",
                    "schema": {
                        "type": "string",
                        "enum": ["certified", "refused", "revoked", "superseded", "expired"],
                    },
                },
                "X-Original-SHA256": {
                    "description": "The SHA-256 of the PDF as stored at issue (`pdf_sha256`)",
                    "schema": {"type": "string", "pattern": "^[0-9a-f]{64}$"},
                },
            },
        },
        304: {"description": "Not modified: the ETag given in If-None-Match still matches."},
        **error_responses(401, 404, 422),
    },
    summary="Download one of this station's certificate PDFs, stamped once no longer in force (ETag)",
)
def read_certificate_pdf(
    number: NumberPath,
    session: SessionDep,
    station: StationDep,
    if_none_match: Annotated[str | None, Header(max_length=1000)] = None,
) -> Response:
    """The PDF rendered at issue, or, once revoked, superseded or expired, that PDF with a stamp across
    every page saying so (file name `NUMBER-REVOKED.pdf` and so on). 404 for another station's."""
    return pdf_response(session, station_certificate(session, number, station), if_none_match)


@router.get(
    "/verify/{number}",
    response_model=VerificationOut,
    response_model_exclude_none=True,
    responses={
        200: {
            "description": "The document and what it means now; only `certified` certifies the vehicle.",
            "content": {"application/json": {"examples": VERIFICATION_EXAMPLES}},
        },
        **error_responses(404, 422),
    },
    summary="Verify a certificate or refusal: public, no key needed",
)
def verify_certificate(
    number: NumberPath,
    request: Request,
    session: SessionDep,
    p: Annotated[
        str | None,
        Query(
            max_length=2000,
            description="The payload of a scanned QR code (the part after /V/, or the old ?p=), "
            "percent-encoded; with it the answer says whether it is genuine for this record.",
        ),
    ] = None,
) -> Response:
    """Only what the paper prints, and the status now: certified, refused, revoked, superseded or expired.

    Only `status: certified` (`in_force: true`) certifies the vehicle; a refusal never does. The same
    answer comes from `GET /verify/{number}` with `Accept: application/json`. `revoked_on` and
    `reason` are there only when revoked, `superseded_by` and `superseded_on` only when superseded,
    `qr`, `qr_reason` and `qr_reason_text` only with `p`. 404 (rule `format`, `check_letter` or
    `exists`) for a number that finds no document: such a paper is not valid. docs/verification.md
    says how to check a QR code offline.
    """
    return api_verification(session, number, payload_param(request) if p else None)
