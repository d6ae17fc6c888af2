"""The regulators' statistics page and its CSV: inspections per day and per station over a period."""

from __future__ import annotations

from collections.abc import Iterator
from datetime import UTC, timedelta

from fastapi import APIRouter
from sqlalchemy import select
from starlette.requests import Request
from starlette.responses import Response

from app.accounts.deps import CurrentLogin
from app.api.ids import IdChoice
from app.i18n.active import gettext as _
from app.i18n.active import pgettext
from app.ids import parse_id
from app.stations.models import Station
from app.statistics.by_model import layout_counts, model_counts
from app.statistics.service import MAX_DAYS, Period, Statistics, busiest, statistics
from app.web.deps import SessionDep
from app.web.formatting import local_today, local_zone
from app.web.forms import FormErrors, query_text, read_date
from app.web.spreadsheet import Cell, csv_download
from app.web.templating import render

router = APIRouter(include_in_schema=False)
DEFAULT_DAYS = 30


def read_filters(
    request: Request, errors: FormErrors, station: str = ""
) -> tuple[dict[str, str], Period, int | None]:
    """The period (default: the last 30 days, today included) and station asked for, or the errors."""
    query = request.query_params
    values = {name: query_text(query.get(name, ""), name, errors, limit=40) for name in ("from", "to")}
    values["station"] = query_text(station, "station", errors, limit=40)
    today = local_today()
    last = read_date(values["to"], "to", errors) or today
    first = read_date(values["from"], "from", errors) or last - timedelta(days=DEFAULT_DAYS - 1)
    if last < first:
        # The fields named as their labels name them, in quotes.
        to_field, from_field = pgettext("the date field", "to"), pgettext("the date field", "from")
        errors.add(
            "to",
            _("The %(to)s date must be the same as or after the %(from)s date")
            % {"to": f"'{to_field}'", "from": f"'{from_field}'"},
        )
        first, last = last - timedelta(days=DEFAULT_DAYS - 1), last
    elif (last - first).days + 1 > MAX_DAYS:
        errors.add("from", _("Choose a period of at most %(days)s days") % {"days": MAX_DAYS})
        first = last - timedelta(days=MAX_DAYS - 1)
    station_id = parse_id(station)
    if station.strip() and station_id is None:
        errors.add("station", _("Choose a station from the list"))
    return values, Period(first, last), station_id


def _statistics(
    request: Request, session: SessionDep, station: str
) -> tuple[dict[str, str], Statistics, FormErrors]:
    errors = FormErrors()
    values, period, station_id = read_filters(request, errors, station)
    return values, statistics(session, period=period, zone=local_zone() or UTC, station_id=station_id), errors


@router.get("/statistics")
def statistics_page(
    request: Request, session: SessionDep, login: CurrentLogin, station: IdChoice = ""
) -> Response:
    """Totals, inspections per day and per station, and certificates, for a period and a station."""
    values, stats, errors = _statistics(request, session, station)
    stations = session.scalars(select(Station).order_by(Station.name)).all()
    zone = local_zone() or UTC
    per_model = model_counts(session, period=stats.period, zone=zone, station_id=parse_id(values["station"]))
    per_layout = layout_counts(
        session, period=stats.period, zone=zone, station_id=parse_id(values["station"])
    )
    return render(
        request,
        "statistics/show.html",
        {
            "values": values,
            "errors": errors.messages,
            "stats": stats,
            "busiest": busiest(stats.days),
            "stations": stations,
            "station_name": next((s.name for s in stations if str(s.id) == values["station"]), None),
            "csv_query": request.url.query,
            "per_model": per_model,
            # Shown once a vehicle of another layout than the study's delta was inspected.
            "per_layout": per_layout if any(row.layout != "delta" for row in per_layout) else [],
        },
        status_code=422 if errors else 200,
    )


@router.get("/statistics.csv")
def statistics_csv(
    request: Request, session: SessionDep, login: CurrentLogin, station: IdChoice = ""
) -> Response:
    """The same period's counts per day as CSV, for a spreadsheet."""
    _values, stats, errors = _statistics(request, session, station)
    if errors:
        return Response("; ".join(errors.messages.values()), status_code=422, media_type="text/plain")
    rows: Iterator[list[Cell]] = (
        [day.day.isoformat(), day.counts.inspections, day.counts.compliant, day.counts.not_compliant]
        for day in stats.days
    )
    name = f"trikecert-statistics-{stats.period.first.isoformat()}-{stats.period.last.isoformat()}.csv"
    return csv_download(["date", "inspections", "compliant", "not_compliant"], rows, name)
