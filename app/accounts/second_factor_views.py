"""The second-factor pages: enrol an authenticator app, enter a code at sign-in, and an admin's reset."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts import second_factor
from app.accounts.deps import ConfirmedAdminPost, PendingLogin, PendingPost
from app.accounts.service import get_user
from app.accounts.sessions import set_flash
from app.accounts.views import safe_next
from app.api.ids import UserId
from app.config import get_settings
from app.errors import ServiceError
from app.i18n.active import gettext as _
from app.i18n.active import ngettext
from app.web.deps import FormDep, SessionDep
from app.web.forms import FormErrors, text
from app.web.templating import render

router = APIRouter(include_in_schema=False)
NextPath = Annotated[str | None, Query(alias="next")]


def _next_field(form: FormDep) -> str:
    """Where to go on afterwards: the form's `next`, if it is a path of this site."""
    value = form.get("next")
    return safe_next(value if isinstance(value, str) else None)


def _code(form: FormDep, errors: FormErrors) -> str:
    """The typed code under the text rule (a refused one is never counted as a wrong code)."""
    return text(form, "code", errors, limit=40)


def _code_page(request: Request, *, next_path: str, errors: FormErrors, status_code: int = 200) -> Response:
    return render(
        request,
        "accounts/code.html",
        {"next_path": next_path, "errors": errors.messages},
        status_code=status_code,
    )


@router.get("/login/code")
def code_form(request: Request, login: PendingLogin, next_path: NextPath = None) -> Response:
    """The second step of signing in: a code from the authenticator app, or a recovery code."""
    if not second_factor.is_enrolled(login.user):
        return RedirectResponse(f"/account/two-factor?next={safe_next(next_path)}", status_code=303)
    return _code_page(request, next_path=safe_next(next_path), errors=FormErrors())


@router.post("/login/code")
def submit_code(request: Request, session: SessionDep, login: PendingPost, form: FormDep) -> Response:
    """Accept the code once and let the session go on, or show the form again with the problem."""
    next_path = _next_field(form)
    errors = FormErrors()
    code = _code(form, errors)
    if errors:
        return _code_page(request, next_path=next_path, errors=errors, status_code=422)
    try:
        kind = second_factor.check_code(session, user=login.user, code=code, settings=get_settings())
    except ServiceError as error:
        errors.add_problems(error.problems, {"code": "code"}, "code")
        return _code_page(request, next_path=next_path, errors=errors, status_code=error.status)
    second_factor.mark_passed(session, login)
    if kind == "recovery code":
        left = second_factor.remaining_recovery_codes(session, user=login.user)
        set_flash(
            session,
            login,
            ngettext(
                "Signed in with a recovery code; it no longer works. %(num)s recovery code is left.",
                "Signed in with a recovery code; it no longer works. %(num)s recovery codes are left.",
                left,
            )
            % {"num": left},
        )
    return RedirectResponse(next_path, status_code=303)


def _enrol_page(
    request: Request,
    *,
    enrolment: second_factor.Enrolment,
    next_path: str,
    errors: FormErrors,
    status_code: int = 200,
) -> Response:
    return render(
        request,
        "accounts/enrol.html",
        {"enrolment": enrolment, "next_path": next_path, "errors": errors.messages},
        status_code=status_code,
    )


@router.get("/account/two-factor")
def enrol_form(
    request: Request, session: SessionDep, login: PendingLogin, next_path: NextPath = None
) -> Response:
    """Set up the second factor: the QR code and the secret in text, and a code to confirm them."""
    if second_factor.is_enrolled(login.user):
        if login.second_factor_at is None:
            return RedirectResponse(f"/login/code?next={safe_next(next_path)}", status_code=303)
        return render(request, "accounts/enrolled.html", {})
    enrolment = second_factor.start_enrolment(session, user=login.user, settings=get_settings())
    return _enrol_page(request, enrolment=enrolment, next_path=safe_next(next_path), errors=FormErrors())


@router.post("/account/two-factor")
def confirm_enrolment(request: Request, session: SessionDep, login: PendingPost, form: FormDep) -> Response:
    """Turn the second factor on once a code from the app is right; show the recovery codes once."""
    next_path = _next_field(form)
    settings = get_settings()
    if second_factor.is_enrolled(login.user):  # set up already: a new phone needs an admin's reset
        return RedirectResponse(f"/account/two-factor?next={next_path}", status_code=303)
    errors = FormErrors()
    code = _code(form, errors)
    if errors:
        enrolment = second_factor.start_enrolment(session, user=login.user, settings=settings)
        return _enrol_page(request, enrolment=enrolment, next_path=next_path, errors=errors, status_code=422)
    try:
        codes = second_factor.confirm_enrolment(session, user=login.user, code=code, settings=settings)
    except ServiceError as error:
        errors.add_problems(error.problems, {"code": "code"}, "code")
        enrolment = second_factor.start_enrolment(session, user=login.user, settings=settings)
        return _enrol_page(
            request, enrolment=enrolment, next_path=next_path, errors=errors, status_code=error.status
        )
    second_factor.mark_passed(session, login)
    return render(request, "accounts/recovery_codes.html", {"codes": codes, "next_path": next_path})


@router.post("/admin/users/{user_id}/two-factor/reset")
def reset_second_factor(session: SessionDep, login: ConfirmedAdminPost, user_id: UserId) -> Response:
    """Remove an account's second factor: it enrols again at its next sign-in (recorded in the audit log)."""
    user = get_user(session, user_id)
    second_factor.reset_second_factor(session, user=user)
    set_flash(
        session,
        login,
        _("The second factor of %(email)s was reset; they set it up again at their next sign-in.")
        % {"email": user.email},
    )
    return RedirectResponse("/admin/users", status_code=303)
