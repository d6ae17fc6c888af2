"""The administrators' audit page: who did what and when, newest first, and whether the record is intact."""

from __future__ import annotations

from fastapi import APIRouter
from starlette.requests import Request
from starlette.responses import Response

from app.audit.checkpoint import verify_since_checkpoint
from app.audit.service import list_events
from app.config import get_settings
from app.ids import PageNumber
from app.web.deps import AdminLogin, SessionDep
from app.web.templating import render

router = APIRouter(prefix="/admin/audit", include_in_schema=False)
PAGE_SIZE = 100


@router.get("")
def audit_page(
    request: Request,
    session: SessionDep,
    login: AdminLogin,
    page: PageNumber = 1,
) -> Response:
    """A page of the audit log, with the check of the whole chain above it."""
    events, total = list_events(session, page=page, page_size=PAGE_SIZE)
    return render(
        request,
        "audit/list.html",
        {
            "events": events,
            "total": total,
            "page": page,
            "pages": max(1, -(-total // PAGE_SIZE)),
            "check": verify_since_checkpoint(session, get_settings()),
            "zone_name": get_settings().display_timezone,
        },
    )
