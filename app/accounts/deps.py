"""Who is signed in, for the pages: the live session (past its second factor, or not yet), the
administrator, a POST carrying the session's CSRF token, and a fresh confirmation before an action
that cannot be undone. Each is an `Annotated` dependency a view declares."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends
from sqlalchemy.orm import Session
from starlette.datastructures import FormData
from starlette.requests import Request

from app.accounts import reauth, second_factor
from app.accounts.models import UserSession
from app.accounts.sessions import load_session, pop_flash
from app.audit.recorder import Actor, act_as
from app.config import get_settings
from app.errors import ServiceError
from app.i18n.active import gettext as _
from app.web import cookies
from app.web.csrf import CsrfRefused, check_session_token
from app.web.deps import ConfirmIdentity, Forbidden, FormDep, SessionDep, SignInRequired
from app.web.forms import FormErrors, secret, text


def _live_session(request: Request, session: Session) -> UserSession | None:
    token = cookies.read_cookie(request, cookies.SESSION)
    if not token:
        return None
    record = load_session(session, token=token, settings=get_settings())
    if record is not None:
        act_as(session, Actor("user", record.user.id, record.user.email))
    return record


def _asked_for(request: Request) -> str:
    return request.url.path + (f"?{request.url.query}" if request.url.query else "")


def _second_factor_gate(request: Request, record: UserSession) -> None:
    """Send a session that has not passed its second factor to the code (or enrolment) page."""
    if not second_factor.passed(record, get_settings()):
        enrolled = second_factor.is_enrolled(record.user)
        raise SignInRequired(_asked_for(request), page="/login/code" if enrolled else "/account/two-factor")


def pending_login(request: Request, session: SessionDep) -> UserSession:
    """A live session, whether or not it has passed its second factor (the code and enrolment pages)."""
    record = _live_session(request, session)
    if record is None:
        raise SignInRequired(_asked_for(request))
    request.state.login = record
    return record


def current_login(request: Request, session: SessionDep) -> UserSession:
    """The signed-in session of a page view, or a redirect to sign in (or to its second factor)."""
    record = _live_session(request, session)
    if record is None:
        raise SignInRequired(_asked_for(request))
    _second_factor_gate(request, record)
    request.state.login = record
    request.state.flash = pop_flash(session, record)
    return record


def pending_post(request: Request, session: SessionDep, form: FormDep) -> UserSession:
    """A POST carrying the session's CSRF token, whether or not it has passed its second factor."""
    record = _live_session(request, session)
    if record is None:
        raise CsrfRefused
    check_session_token(form, record.csrf_token)
    request.state.login = record
    return record


def checked_post(request: Request, session: SessionDep, form: FormDep) -> UserSession:
    """A POST from a signed-in session (past its second factor) carrying that session's CSRF token;
    anything else is 403 (or, before the second factor, a redirect to it)."""
    record = pending_post(request, session, form)
    _second_factor_gate(request, record)
    return record


PendingLogin = Annotated[UserSession, Depends(pending_login)]
PendingPost = Annotated[UserSession, Depends(pending_post)]
CurrentLogin = Annotated[UserSession, Depends(current_login)]
PostLogin = Annotated[UserSession, Depends(checked_post)]


def admin_login(login: CurrentLogin) -> UserSession:
    """A page view by an administrator."""
    if login.user.role != "admin":
        raise Forbidden
    return login


def admin_post(login: PostLogin) -> UserSession:
    """A checked POST by an administrator."""
    if login.user.role != "admin":
        raise Forbidden
    return login


AdminLogin = Annotated[UserSession, Depends(admin_login)]
AdminPost = Annotated[UserSession, Depends(admin_post)]

_CONFIRMATION_FIELDS = {"csrf_token", reauth.PASSWORD_FIELD, reauth.CODE_FIELD}


def _carried(form: FormData) -> list[tuple[str, str]]:
    return [
        (name, value)
        for name, value in form.multi_items()
        if isinstance(value, str) and name not in _CONFIRMATION_FIELDS
    ]


def _confirmed(request: Request, session: Session, login: UserSession, form: FormData) -> UserSession:
    """The session, once it proved who it is within five minutes (now, from this form, if need be)."""
    if reauth.is_fresh(login):
        return login
    errors = FormErrors()
    if reauth.PASSWORD_FIELD in form:
        password = secret(form, reauth.PASSWORD_FIELD, errors, limit=1000)
        code = text(form, reauth.CODE_FIELD, errors, limit=40)
        if not password:
            errors.add(reauth.PASSWORD_FIELD, _("Enter your password"))
        if not code and reauth.needs_code(login, get_settings()):
            errors.add(reauth.CODE_FIELD, _("Enter the 6-digit code your app shows now"))
        if not errors:
            try:
                reauth.confirm(
                    session,
                    record=login,
                    password=password,
                    code=code,
                    client_ip=request.client.host if request.client else None,
                    settings=get_settings(),
                )
                return login
            except ServiceError as error:
                errors.add_problems(
                    error.problems,
                    {reauth.PASSWORD_FIELD: reauth.PASSWORD_FIELD, reauth.CODE_FIELD: reauth.CODE_FIELD},
                    reauth.PASSWORD_FIELD,
                )
    raise ConfirmIdentity(
        action=request.url.path,
        fields=_carried(form),
        errors=errors.messages,
        status=422 if errors else 401,
        needs_code=reauth.needs_code(login, get_settings()),
    )


def confirmed_post(request: Request, session: SessionDep, login: PostLogin, form: FormDep) -> UserSession:
    """A checked POST that cannot be undone: the password and code again if the last check is old."""
    return _confirmed(request, session, login, form)


def confirmed_admin_post(
    request: Request, session: SessionDep, login: AdminPost, form: FormDep
) -> UserSession:
    """A checked POST by an administrator that cannot be undone (see confirmed_post)."""
    return _confirmed(request, session, login, form)


ConfirmedPost = Annotated[UserSession, Depends(confirmed_post)]
ConfirmedAdminPost = Annotated[UserSession, Depends(confirmed_admin_post)]


def offers_navigation(login: UserSession) -> bool:
    """The layout offers its navigation once the session has passed its second factor (before it,
    the pages behind it would only send the officer back)."""
    return second_factor.passed(login, get_settings())
