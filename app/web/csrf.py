"""CSRF tokens: a per-session synchronizer token, and a double-submit cookie for the sign-in form."""

from __future__ import annotations

import hmac
import secrets

from starlette.datastructures import FormData
from starlette.requests import Request

from app.web import cookies

FIELD = "csrf_token"


class CsrfRefused(Exception):
    """A POST without a valid CSRF token: answered 403, nothing done."""


def form_token(form: FormData) -> str:
    """The token a form carried, or empty."""
    value = form.get(FIELD)
    return value if isinstance(value, str) else ""


def check_session_token(form: FormData, expected: str) -> None:
    """Refuse a form whose token is not the session's."""
    if not expected or not hmac.compare_digest(form_token(form).encode(), expected.encode()):
        raise CsrfRefused


def login_token(request: Request) -> tuple[str, bool]:
    """The sign-in form's token from its cookie, or a new one; True when the cookie must be set."""
    current = cookies.read_cookie(request, cookies.LOGIN_CSRF)
    if current and 20 <= len(current) <= 64:
        return current, False
    return secrets.token_urlsafe(32), True


def check_login_token(request: Request, form: FormData) -> None:
    """Refuse a sign-in whose form token does not match its cookie (double submit)."""
    expected = cookies.read_cookie(request, cookies.LOGIN_CSRF) or ""
    check_session_token(form, expected)
