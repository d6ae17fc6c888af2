"""Sign in and sign out pages."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.accounts import throttle
from app.accounts.login import sign_in
from app.accounts.service import EMAIL_LENGTH, MAX_PASSWORD_LENGTH
from app.accounts.sessions import end_session, load_session
from app.audit.recorder import Actor, act_as, record_event
from app.config import get_settings
from app.db import begin_write
from app.i18n.active import N_, ngettext
from app.i18n.active import gettext as _
from app.text import character_problem
from app.web import cookies, csrf
from app.web.deps import FormDep, SessionDep
from app.web.forms import FormErrors, secret, text
from app.web.templating import render

router = APIRouter(include_in_schema=False)
MAX_NEXT_LENGTH = 500

REFUSALS = {
    throttle.BAD_CREDENTIALS: (401, N_("Enter a correct email address and password")),
    throttle.DISABLED: (403, N_("This account has been disabled. Ask an administrator to enable it")),
}


def locked_out_message(locked: throttle.LockedOut) -> str:
    """Why sign-in is refused for now, and for how long."""
    wait = ngettext(
        "Wait %(num)s minute, then try again", "Wait %(num)s minutes, then try again", locked.wait_minutes
    ) % {"num": locked.wait_minutes}
    if locked.scope == throttle.ADDRESS:
        return _("There have been too many failed sign-ins from this network. %(wait)s") % {"wait": wait}
    return _("There have been too many failed sign-ins for this account. %(wait)s") % {"wait": wait}


def safe_next(path: str | None) -> str:
    """Only a path on this site may follow sign-in (never another host); home instead of any other.

    It comes from a hidden field or the query string, so a path that breaks the text rule (a NUL or a
    line break could never go into the Location header) or is too long is dropped, not refused:
    nobody could correct it.
    """
    if not path or len(path) > MAX_NEXT_LENGTH or character_problem(path) is not None:
        return "/"
    if not path.startswith("/") or path.startswith(("//", "/\\")) or path.startswith("/login"):
        return "/"
    return path


def _login_page(
    request: Request,
    *,
    values: dict[str, str],
    errors: FormErrors,
    status_code: int,
    next_path: str,
    notice: str = "",
) -> Response:
    token, is_new = csrf.login_token(request)
    response = render(
        request,
        "accounts/login.html",
        {
            "login_csrf": token,
            "values": values,
            "errors": errors.messages,
            "next_path": next_path,
            "notice": notice,
        },
        status_code=status_code,
    )
    if is_new:
        cookies.write_cookie(response, request, cookies.LOGIN_CSRF, token, samesite="strict")
    return response


@router.get("/login")
def login_form(
    request: Request,
    session: SessionDep,
    next_path: Annotated[str | None, Query(alias="next")] = None,
    signed_out: Annotated[str | None, Query()] = None,
) -> Response:
    """The sign-in form (a signed-in officer goes straight on)."""
    token = cookies.read_cookie(request, cookies.SESSION)
    if token and load_session(session, token=token, settings=get_settings()) is not None:
        return RedirectResponse(safe_next(next_path), status_code=303)
    notice = _("You have signed out.") if signed_out else ""
    return _login_page(
        request,
        values={},
        errors=FormErrors(),
        status_code=200,
        next_path=safe_next(next_path),
        notice=notice,
    )


@router.post("/login")
def login(request: Request, session: SessionDep, form: FormDep) -> Response:
    """Check the form token and the credentials; on success a new session id, then 303 onwards."""
    csrf.check_login_token(request, form)
    errors = FormErrors()
    email = text(form, "email", errors, limit=EMAIL_LENGTH)
    password = secret(form, "password", errors, limit=MAX_PASSWORD_LENGTH)
    next_field = form.get("next")
    next_path = safe_next(next_field if isinstance(next_field, str) else None)
    if not email:
        errors.add("email", _("Enter your email address"))
    if not password:
        errors.add("password", _("Enter your password"))
    if errors:
        return _login_page(
            request, values={"email": email}, errors=errors, status_code=422, next_path=next_path
        )
    settings = get_settings()
    client_ip = request.client.host if request.client else None
    result = sign_in(session, email=email, password=password, client_ip=client_ip, settings=settings)
    if result.started is None:
        if result.locked is not None:
            status, message = 429, locked_out_message(result.locked)
        else:
            status, refusal = REFUSALS[result.outcome]
            message = _(refusal)
        errors.add("email", message)
        return _login_page(
            request, values={"email": email}, errors=errors, status_code=status, next_path=next_path
        )
    previous = cookies.read_cookie(request, cookies.SESSION)
    if previous:
        end_session(session, token=previous)
    response = RedirectResponse(next_path, status_code=303)
    cookies.write_cookie(response, request, cookies.SESSION, result.started.token)
    cookies.clear_cookie(response, request, cookies.LOGIN_CSRF)
    return response


@router.post("/logout")
def logout(request: Request, session: SessionDep, form: FormDep) -> Response:
    """End the session on the server and forget the cookie."""
    token = cookies.read_cookie(request, cookies.SESSION)
    record = load_session(session, token=token, settings=get_settings()) if token else None
    if record is not None:
        csrf.check_session_token(form, record.csrf_token)
        act_as(session, Actor("user", record.user.id, record.user.email))
        begin_write(session)
        record_event(session, action="sign_out", target_type="user", target_id=record.user_id, details={})
        end_session(session, token=token or "")
    response = RedirectResponse("/login?signed_out=1", status_code=303)
    cookies.clear_cookie(response, request, cookies.SESSION)
    return response
