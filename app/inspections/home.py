"""The home page: today's counts of inspections, compliant and not compliant."""

from __future__ import annotations

from fastapi import APIRouter
from starlette.requests import Request
from starlette.responses import Response

from app.accounts.deps import CurrentLogin
from app.inspections.service import InspectionFilter, list_inspections
from app.web.deps import SessionDep
from app.web.formatting import day_bounds, local_today
from app.web.templating import render

router = APIRouter(include_in_schema=False)
LATEST = 5


@router.get("/")
def home(request: Request, session: SessionDep, login: CurrentLogin) -> Response:
    """Today's counts and latest inspections, with the main tasks."""
    today = local_today()
    since, until = day_bounds(today)
    latest, total = list_inspections(
        session, where=InspectionFilter(since=since, until=until), limit=LATEST, offset=0
    )
    _none, compliant = list_inspections(
        session, where=InspectionFilter(since=since, until=until, compliant=True), limit=1, offset=0
    )
    return render(
        request,
        "home.html",
        {
            "today": today,
            "counts": {"total": total, "compliant": compliant, "not_compliant": total - compliant},
            "latest": latest,
        },
    )
