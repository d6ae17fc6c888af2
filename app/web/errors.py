"""Refusals on the pages as HTML (403, 404, sign-in redirects); the API keeps its JSON answers."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from urllib.parse import urlencode

from fastapi import FastAPI
from fastapi.exceptions import RequestValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response

from app.api.errors import DATABASE_ERRORS, note_outage, retry_later_headers
from app.db import is_outage
from app.errors import ServiceError
from app.i18n.active import N_
from app.i18n.active import gettext as _
from app.web.csrf import CsrfRefused
from app.web.deps import ConfirmIdentity, Forbidden, SignInRequired
from app.web.templating import render

Handler = Callable[[Request, Exception], Awaitable[Response]]

# Marked here, translated when a page is drawn (the request's language).
TITLES = {
    400: N_("Sorry, there is a problem with this request"),
    403: N_("You cannot do that"),
    404: N_("Page not found"),
    405: N_("Sorry, that did not work"),
    413: N_("The form is too large"),
    422: N_("Sorry, there is a problem with this request"),
    503: N_("Sorry, the service is not available right now"),
}
UNKNOWN_TITLE = N_("Sorry, there is a problem")
NOT_FOUND = N_("Check the address, or use the links above.")


def wants_html(request: Request) -> bool:
    """A page request: not the API or the SMS gateway's callbacks, and a browser asking for HTML."""
    if request.url.path.startswith(("/api/", "/gateway/")):
        return False
    return "text/html" in request.headers.get("accept", "") or request.method == "POST"


def error_page(
    request: Request, status: int, message: str, *, title: str | None = None, retry_url: str | None = None
) -> Response:
    """The HTML page of a refusal; `retry_url` offers to load the page again instead of going home."""
    return render(
        request,
        "errors/error.html",
        {
            # A message with no translation (a service error's own text) stays as it is.
            "title": _(title or TITLES.get(status, UNKNOWN_TITLE)),
            "message": _(message),
            "status": status,
            "retry_url": retry_url,
        },
        status_code=status,
    )


async def on_sign_in_required(request: Request, exc: Exception) -> Response:
    """Send the browser to the sign-in page, remembering where it was going."""
    assert isinstance(exc, SignInRequired)
    query = urlencode({"next": exc.next_path}) if exc.next_path not in ("", "/") else ""
    return RedirectResponse(f"{exc.page}?{query}" if query else exc.page, status_code=303)


async def on_csrf_refused(request: Request, _exc: Exception) -> Response:
    """403: the form was not sent by this site's page, or the session has ended."""
    return error_page(
        request,
        403,
        N_(
            "The form was out of date or did not come from this service, so nothing was saved. "
            "Sign in again if you need to, go back, reload the page and try again."
        ),
        title=N_("Sorry, you will have to start again"),
    )


async def on_forbidden(request: Request, _exc: Exception) -> Response:
    """403: the role does not allow the page."""
    return error_page(request, 403, N_("Only an administrator can use this page."))


async def on_confirm_identity(request: Request, exc: Exception) -> Response:
    """Ask for the password (and a code) again, carrying the form so the action goes on after."""
    assert isinstance(exc, ConfirmIdentity)
    return render(
        request,
        "accounts/confirm.html",
        {
            "action": exc.action,
            "fields": exc.fields,
            "errors": exc.errors,
            "needs_code": exc.needs_code,
        },
        status_code=exc.status,
    )


def _fallback(previous: Handler | None, html: Callable[[Request, Exception], Response]) -> Handler:
    async def handler(request: Request, exc: Exception) -> Response:
        if wants_html(request) or previous is None:
            return html(request, exc)
        return await previous(request, exc)

    return handler


def _http_page(request: Request, exc: Exception) -> Response:
    assert isinstance(exc, StarletteHTTPException)
    message = NOT_FOUND if exc.status_code == 404 else str(exc.detail)
    return error_page(request, exc.status_code, message)


def _service_page(request: Request, exc: Exception) -> Response:
    assert isinstance(exc, ServiceError)
    message = exc.message.split(": ", 1)[-1] if exc.problems else exc.message
    return error_page(request, exc.status, message[:1].upper() + message[1:])


def _validation_page(request: Request, _exc: Exception) -> Response:
    return error_page(request, 404, NOT_FOUND)


def _outage_page(request: Request, exc: Exception) -> Response:
    if not is_outage(exc):
        raise exc
    note_outage(request, exc)
    # The layout would show the signed-in officer, whose record may not be loaded yet: no database now.
    request.state.login = None
    if request.method == "GET":
        query = f"?{request.url.query}" if request.url.query else ""
        message = N_("The database is not answering. Try again in a moment.")
        retry_url = request.url.path + query
    else:
        message, retry_url = (
            N_(
                "The database is not answering, so this may not have been saved. In a moment, "
                "go back and send the form again: a form sent twice is stored only once."
            ),
            None,
        )
    response = error_page(request, 503, message, retry_url=retry_url)
    response.headers.update(retry_later_headers())
    return response


def install_web_error_handlers(app: FastAPI) -> None:
    """Answer page requests in HTML; hand API requests to the handlers already installed."""
    app.add_exception_handler(SignInRequired, on_sign_in_required)
    app.add_exception_handler(CsrfRefused, on_csrf_refused)
    app.add_exception_handler(Forbidden, on_forbidden)
    app.add_exception_handler(ConfirmIdentity, on_confirm_identity)
    pages: list[tuple[type[Exception], Callable[[Request, Exception], Response]]] = [
        (StarletteHTTPException, _http_page),
        (ServiceError, _service_page),
        (RequestValidationError, _validation_page),
        *((kind, _outage_page) for kind in DATABASE_ERRORS),
    ]
    for kind, page in pages:
        previous = app.exception_handlers.get(kind)
        app.add_exception_handler(kind, _fallback(previous, page))  # type: ignore[arg-type]
