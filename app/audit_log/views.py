"""The administrators' audit page: who did what and when, newest first, filtered by who, what, which
record and when, with the check of the whole record above it and the same events as CSV."""

from __future__ import annotations

import re
from datetime import UTC
from typing import Annotated

from fastapi import APIRouter, Depends, Query
from starlette.requests import Request
from starlette.responses import Response

from app.accounts.deps import AdminLogin
from app.api.ids import PageNumber
from app.audit.models import AuditEvent
from app.audit_log import words
from app.audit_log.checkpoint import verify_since_checkpoint
from app.audit_log.service import (
    ACTOR_KINDS,
    AuditFilter,
    actions_on_record,
    all_events,
    list_events,
    record_types_on_record,
)
from app.config import get_settings
from app.i18n.active import gettext as _
from app.web.deps import SessionDep
from app.web.formatting import day_bounds, local_today, long_date, to_local
from app.web.forms import FormErrors, query_text, read_date
from app.web.spreadsheet import Cell, csv_download
from app.web.templating import render

router = APIRouter(prefix="/admin/audit", include_in_schema=False)
PAGE_SIZE = 100
# The filters and the most each may hold (an actor's label and a record id as the log keeps them).
LIMITS = {
    "actor": 300,
    "actor_kind": 40,
    "action": 64,
    "record_type": 40,
    "record_id": 64,
    "from": 40,
    "to": 40,
}
ACTION = re.compile(r"[a-z][a-z_]*\.(?:[a-z][a-z_]*)?")  # "certificate.issued", or "certificate." for all
RECORD_TYPE = re.compile(r"[a-z][a-z_]*")
CSV_HEADER = [
    "id",
    "occurred_at_utc",
    "occurred_at_local",
    "actor_kind",
    "actor_label",
    "action",
    "record_type",
    "record_id",
    "details",
    "client_address",
    "request_id",
    "hash",
]


def filter_query(
    actor: str = "",
    actor_kind: str = "",
    action: str = "",
    record_type: str = "",
    record_id: str = "",
    since: Annotated[str, Query(alias="from")] = "",
    until: Annotated[str, Query(alias="to")] = "",
) -> dict[str, str]:
    """The filters as sent, unchecked (declared one by one so that the route walks in the tests try each)."""
    return {
        "actor": actor,
        "actor_kind": actor_kind,
        "action": action,
        "record_type": record_type,
        "record_id": record_id,
        "from": since,
        "to": until,
    }


FilterQuery = Annotated[dict[str, str], Depends(filter_query)]


def read_filters(sent: dict[str, str], errors: FormErrors) -> tuple[dict[str, str], AuditFilter]:
    """The filters under the text rule and their own checks; a refused one is blank, its message added."""
    values = {name: query_text(sent[name], name, errors, limit=limit) for name, limit in LIMITS.items()}
    if values["actor_kind"] not in ("", *ACTOR_KINDS):
        errors.add("actor_kind", _("Choose a kind of actor from the list"))
        values["actor_kind"] = ""
    if values["action"] and not ACTION.fullmatch(values["action"]):
        errors.add("action", _("Choose an action from the list"))
        values["action"] = ""
    if values["record_type"] and not RECORD_TYPE.fullmatch(values["record_type"]):
        errors.add("record_type", _("Choose a kind of record from the list"))
        values["record_type"] = ""
    since_day, until_day = read_date(values["from"], "from", errors), read_date(values["to"], "to", errors)
    if since_day and until_day and until_day < since_day:
        errors.add(
            "to",
            _("The %(to)s date must be the same as or after the %(from)s date")
            % {"to": "'to'", "from": "'from'"},
        )
        until_day = None
    where = AuditFilter(
        actor=values["actor"],
        actor_kind=values["actor_kind"],
        action=values["action"],
        target_type=values["record_type"],
        target_id=values["record_id"],
        since=day_bounds(since_day)[0] if since_day else None,
        until=day_bounds(until_day)[1] if until_day else None,
    )
    return values, where


def action_groups(actions: list[str]) -> list[tuple[str, list[str]]]:
    """The actions grouped by the kind of record they start with ("certificate."), in order; an action
    with no kind of its own ("sign_out") is its group's only one, chosen by the group alone."""
    groups: dict[str, list[str]] = {}
    for action in sorted(actions):
        kind, dot, _rest = action.partition(".")
        groups.setdefault(kind + ".", [])
        if dot:
            groups[kind + "."].append(action)
    return list(groups.items())


@router.get("")
def audit_page(
    request: Request,
    session: SessionDep,
    login: AdminLogin,
    sent: FilterQuery,
    page: PageNumber = 1,
) -> Response:
    """A page of the events the filters pick, with the check of the whole chain above it."""
    errors = FormErrors()
    values, where = read_filters(sent, errors)
    events, total = list_events(session, page=page, page_size=PAGE_SIZE, where=where)
    actions = set(actions_on_record(session))
    if values["action"] and not values["action"].endswith("."):
        actions.add(values["action"])  # a well-formed action nobody has done yet: shown as chosen
    record_types = set(record_types_on_record(session)) | ({values["record_type"]} - {""})
    kept = {name: value for name, value in values.items() if value and name not in errors.messages}
    return render(
        request,
        "audit/list.html",
        {
            "events": events,
            "total": total,
            "page": page,
            "pages": max(1, -(-total // PAGE_SIZE)),
            "first": (page - 1) * PAGE_SIZE + 1 if events else 0,
            "last": (page - 1) * PAGE_SIZE + len(events),
            "check": verify_since_checkpoint(session, get_settings()),
            "zone_name": get_settings().display_timezone,
            "values": values,
            "errors": errors.messages,
            "kept": kept,
            "actor_kinds": ACTOR_KINDS,
            "action_groups": action_groups(sorted(actions)),
            "record_types": sorted(record_types),
            "today": long_date(local_today()),
            "action_words": words.action_words,
            "record_kind": words.record_kind,
            "actor_kind": words.actor_kind,
            "actor_label": words.actor_label,
            "first_upper": words.first_upper,
        },
        status_code=422 if errors else 200,
    )


def csv_row(event: AuditEvent) -> list[Cell]:
    """One event as a row of the CSV, its time in UTC and in the display zone."""
    moment = event.occurred_at.astimezone(UTC)
    return [
        event.id,
        moment.strftime("%Y-%m-%dT%H:%M:%S.%fZ"),
        to_local(moment).isoformat(timespec="microseconds"),
        event.actor_kind,
        event.actor_label,
        event.action,
        event.target_type,
        event.target_id,
        event.details,
        event.client_address,
        event.request_id,
        event.hash,
    ]


@router.get(".csv")
def audit_csv(session: SessionDep, login: AdminLogin, sent: FilterQuery) -> Response:
    """Every event the filters pick (not only a page), newest first, as CSV for a spreadsheet."""
    errors = FormErrors()
    values, where = read_filters(sent, errors)
    if errors:
        return Response("; ".join(errors.messages.values()), status_code=422, media_type="text/plain")
    rows = (csv_row(event) for event in all_events(session, where))
    name = f"trikecert-audit-{values['from'] or 'start'}-{values['to'] or local_today().isoformat()}.csv"
    return csv_download(CSV_HEADER, rows, name)
