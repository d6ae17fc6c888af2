"""One-time form tokens: the first submission stores its result page; a repeat is sent there too."""

from __future__ import annotations

import secrets

from sqlalchemy.orm import Session

from app.web.models import FormSubmission


def new_form_token() -> str:
    """A fresh token for a form about to be shown (nothing is stored until it is submitted)."""
    return secrets.token_urlsafe(24)


def valid_token(token: str) -> bool:
    """A token this service could have issued."""
    return 20 <= len(token) <= 64 and all(c.isalnum() or c in "-_" for c in token)


def previous_result(session: Session, token: str) -> str | None:
    """The page the first submission of this form led to, or None."""
    used = session.get(FormSubmission, token)
    return used.redirect_path if used is not None else None


def remember(session: Session, *, token: str, user_id: int | None, redirect_path: str) -> None:
    """Add the used token to the session's transaction (the caller commits it with its result)."""
    session.add(FormSubmission(token=token, user_id=user_id, redirect_path=redirect_path))
