"""Certificate actions in the officers' pages: issue from an inspection, download the PDF, revoke (admins)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Header, Path
from sqlalchemy.orm import Session, object_session
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts.deps import ConfirmedAdminPost, CurrentLogin, PostLogin
from app.accounts.sessions import set_flash
from app.api.ids import InspectionId
from app.certificates.actors import Actor, issued_by, recorded_by
from app.certificates.facts import Facts
from app.certificates.models import Certificate
from app.certificates.pdf_response import pdf_response
from app.certificates.records import get_certificate
from app.certificates.service import REASON_LENGTH, issue_certificate, revoke_certificate
from app.certificates.views import document_context
from app.config import get_settings
from app.errors import ServiceError
from app.i18n.active import N_
from app.inspections.models import Inspection
from app.web.deps import FormDep, SessionDep
from app.web.formatting import not_recorded
from app.web.forms import FormErrors, text
from app.web.templating import render
from app.wording import document_kind, issued_message, revoked_message

router = APIRouter(include_in_schema=False)
NumberPath = Annotated[str, Path(max_length=60)]


def certificate_page(
    request: Request, certificate: Certificate, *, errors: dict[str, str] | None = None, reason: str = ""
) -> Response:
    """The certificate as the public sees it, with the officer's download link and the admin's revoke form."""
    context = document_context(certificate)
    session = object_session(certificate)
    assert session is not None
    context.update(
        officer=True,
        people=people_of(session, certificate, context["facts"]),
        errors=errors or {},
        values={"reason": reason},
    )
    return render(request, "certificates/verify.html", context, status_code=422 if errors else 200)


def people_of(session: Session, certificate: Certificate, facts: Facts) -> list[tuple[str, str]]:
    """Who recorded the weighing and who issued the document, by name and badge as the accounts
    have them now (older documents printed an email), and the calibration the document printed."""
    inspection = session.get(Inspection, certificate.inspection_id)
    assert inspection is not None
    issuer = issued_by(
        session,
        user_id=certificate.issued_by_user_id,
        station_id=certificate.issued_by_station_id,
        label=certificate.issued_by,
    )
    return [
        (N_("Weighing recorded by"), recorded_by(session, inspection)),
        (N_("Issued by"), issuer),
        (N_("Scale calibration"), facts.inspection.scale_calibration or not_recorded()),
    ]


@router.post("/inspections/{inspection_id}/certificate")
def issue_from_page(
    inspection_id: InspectionId, session: SessionDep, login: PostLogin, form: FormDep
) -> Response:
    """Issue (or find) the inspection's certificate in the languages chosen, then show it."""
    chosen = form.get("second_language")
    try:
        issued = issue_certificate(
            session,
            inspection_id=inspection_id,
            actor=Actor.of_user(login.user),
            settings=get_settings(),
            second_language=chosen if isinstance(chosen, str) else None,
        )
    except ServiceError as error:
        set_flash(session, login, error.message.split(": ", 1)[-1])
        return RedirectResponse(f"/inspections/{inspection_id}", status_code=303)
    number = issued.certificate.number
    set_flash(session, login, issued_message(issued.certificate.kind, number, issued.created))
    return RedirectResponse(f"/certificates/{number}", status_code=303)


@router.get("/certificates/{number}")
def officer_certificate_page(
    request: Request, number: NumberPath, session: SessionDep, _login: CurrentLogin
) -> Response:
    """The certificate with its status, a PDF download and (for admins) the revoke form."""
    return certificate_page(request, get_certificate(session, number))


@router.get("/certificates/{number}/pdf")
def officer_certificate_pdf(
    number: NumberPath,
    session: SessionDep,
    _login: CurrentLogin,
    if_none_match: Annotated[str | None, Header(max_length=1000)] = None,
) -> Response:
    """The stored PDF, stamped once no longer in force, as the station API serves it (ETag, 304)."""
    return pdf_response(session, get_certificate(session, number), if_none_match)


@router.post("/certificates/{number}/revoke")
def revoke_from_page(
    request: Request, number: NumberPath, session: SessionDep, login: ConfirmedAdminPost, form: FormDep
) -> Response:
    """Revoke with a reason (administrators only, having proved who they are within five minutes),
    then show the certificate."""
    certificate = get_certificate(session, number)
    errors = FormErrors()
    reason = text(form, "reason", errors, limit=REASON_LENGTH)
    if not reason:
        errors.add("reason", f"Enter the reason for revoking this {document_kind(certificate.kind)}")
    if errors:
        return certificate_page(request, certificate, errors=errors.messages, reason=reason)
    revoke_certificate(session, number=certificate.number, actor=Actor.of_user(login.user), reason=reason)
    set_flash(session, login, revoked_message(certificate.kind, certificate.number))
    return RedirectResponse(f"/certificates/{certificate.number}", status_code=303)
