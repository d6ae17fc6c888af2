"""The settings in force when the service starts, recorded in the audit log (never a secret)."""

from __future__ import annotations

from typing import Any

from pydantic import SecretStr
from sqlalchemy import make_url
from sqlalchemy.orm import Session

from app import __version__
from app.audit.recorder import record_event
from app.config import Settings
from app.db import begin_write


def settings_in_force(settings: Settings) -> dict[str, Any]:
    """Every setting as the service will use it; secrets only as whether they are set."""
    shown: dict[str, Any] = {}
    for name in type(settings).model_fields:
        value = getattr(settings, name)
        if isinstance(value, SecretStr):
            shown[name] = "(set)"
        elif name == "database_url":
            shown[name] = make_url(value).render_as_string(hide_password=True)
        else:
            shown[name] = value
    shown["mfa"] = settings.mfa_mode()
    return dict(sorted(shown.items()))


def record_start(session: Session, settings: Settings) -> None:
    """One `service.started` event with the version and the settings in force."""
    begin_write(session)
    details = {"version": __version__, "settings": settings_in_force(settings)}
    record_event(session, action="service.started", target_type="service", target_id=None, details=details)
    session.commit()
