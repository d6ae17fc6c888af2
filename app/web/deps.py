"""What every page's route shares: the database session, the posted form, and the refusals a page
dependency raises (answered as HTML by app/web/errors.py). Who is signed in: app/accounts/deps.py."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends
from sqlalchemy.orm import Session
from starlette.datastructures import FormData
from starlette.requests import Request

from app.db import get_session

SessionDep = Annotated[Session, Depends(get_session)]


class SignInRequired(Exception):
    """No live session (or one still to pass its second factor): the browser is sent to `page`
    (the sign-in page, the code page or the enrolment page), then back to `next_path`."""

    def __init__(self, next_path: str, page: str = "/login") -> None:
        super().__init__(next_path)
        self.next_path = next_path
        self.page = page


class Forbidden(Exception):
    """Signed in, but the role does not allow this page (403)."""


class ConfirmIdentity(Exception):
    """An action that cannot be undone, from a session whose last check is over five minutes old:
    the page asks for the password (and a code, when `needs_code`) again and posts the same form
    back, so the action goes on once they are right. `fields` are the form's own values, carried as
    hidden inputs."""

    def __init__(
        self,
        *,
        action: str,
        fields: list[tuple[str, str]],
        errors: dict[str, str],
        status: int,
        needs_code: bool,
    ) -> None:
        super().__init__(action)
        self.action = action
        self.fields = fields
        self.errors = errors
        self.status = status
        self.needs_code = needs_code


async def form_data(request: Request) -> FormData:
    """The posted form (read once, shared by the CSRF check and the view)."""
    return await request.form()


FormDep = Annotated[FormData, Depends(form_data)]
