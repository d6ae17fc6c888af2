"""Cookie names and attributes: HttpOnly, SameSite, and Secure with a __Host- name over HTTPS."""

from __future__ import annotations

from typing import Literal

from starlette.requests import Request
from starlette.responses import Response

from app.config import get_settings

SESSION = "trikecert_session"
LOGIN_CSRF = "trikecert_login_csrf"


def is_secure(request: Request) -> bool:
    """True when cookies must be Secure: the settings say so or the request came over HTTPS."""
    return get_settings().cookie_secure or request.url.scheme == "https"


def cookie_name(request: Request, base: str) -> str:
    """The cookie's name; over HTTPS the __Host- prefix pins it to this host and path /."""
    return f"__Host-{base}" if is_secure(request) else base


def read_cookie(request: Request, base: str) -> str | None:
    """The cookie's value, or None."""
    return request.cookies.get(cookie_name(request, base)) or None


def write_cookie(
    response: Response, request: Request, base: str, value: str, *, samesite: Literal["lax", "strict"] = "lax"
) -> None:
    """Set a browser-session cookie that scripts cannot read."""
    response.set_cookie(
        cookie_name(request, base),
        value,
        path="/",
        secure=is_secure(request),
        httponly=True,
        samesite=samesite,
    )


def clear_cookie(response: Response, request: Request, base: str) -> None:
    """Tell the browser to forget the cookie."""
    response.delete_cookie(
        cookie_name(request, base), path="/", secure=is_secure(request), httponly=True, samesite="lax"
    )
