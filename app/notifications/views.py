"""The public page /reminders (an email address asks for reminders about a plate; no JavaScript), its
confirm and unsubscribe links, and the admins' counts (never a contact)."""

from __future__ import annotations

from datetime import date, timedelta
from typing import Annotated

from fastapi import APIRouter, Path
from sqlalchemy import func, select
from sqlalchemy.orm import Session
from starlette.requests import Request
from starlette.responses import Response

from app.accounts.deps import AdminLogin
from app.config import get_settings
from app.db import utcnow
from app.i18n.active import current_locale
from app.i18n.active import gettext as _
from app.notifications import service
from app.notifications.contacts import ContactRefused, mask_email, normalise_email
from app.notifications.models import NotificationDay, OutboxMessage, Subscription
from app.vehicles.service import display_registration, find_vehicle
from app.web import cookies, csrf
from app.web.deps import FormDep, SessionDep
from app.web.formatting import local_today
from app.web.forms import FormErrors, text
from app.web.templating import render

router = APIRouter(include_in_schema=False)
TOKEN = Annotated[str, Path(min_length=20, max_length=64, pattern=r"^[A-Za-z0-9_\-]+$")]


def _form(
    request: Request, values: dict[str, str], errors: FormErrors, status_code: int = 200, notice: str = ""
) -> Response:
    token, is_new = csrf.login_token(request)
    response = render(
        request,
        "notifications/reminders.html",
        {"form_csrf": token, "values": values, "errors": errors.messages, "notice": notice},
        status_code=status_code,
    )
    if is_new:
        cookies.write_cookie(response, request, cookies.LOGIN_CSRF, token, samesite="strict")
    return response


@router.get("/reminders")
def reminders_form(request: Request) -> Response:
    """Ask for an email address and a plate."""
    return _form(request, {}, FormErrors())


@router.post("/reminders")
def reminders_subscribe(request: Request, session: SessionDep, form: FormDep) -> Response:
    """Send a confirmation link to the address; nothing else is sent before it is opened."""
    csrf.check_login_token(request, form)
    errors = FormErrors()  # in the form's order: the summary lists them so
    plate = text(form, "plate", errors, limit=32)
    email_text = text(form, "email", errors, limit=254)
    values = {"email": email_text, "plate": plate}
    vehicle = None
    if not plate and "plate" not in errors.messages:
        errors.add("plate", _("Enter the plate, like BDG 252 QH"))
    elif plate:
        vehicle = find_vehicle(session, plate)
        if vehicle is None:
            errors.add(
                "plate",
                _("No keke %(plate)s is registered: check the plate")
                % {"plate": display_registration(plate)},
            )
    email = ""
    if not email_text and "email" not in errors.messages:
        errors.add("email", _("Enter your email address"))
    elif email_text:
        try:
            email = normalise_email(email_text)
        except ContactRefused:  # its reason is in English, and says no more than this
            errors.add("email", _("Enter an email address like name@example.com"))
    if errors or vehicle is None:
        return _form(request, values, errors, status_code=422)
    client = request.client.host if request.client else ""
    try:
        subscribed = service.subscribe(
            session,
            vehicle=vehicle,
            channel="email",
            contact=email,
            client=client,
            settings=get_settings(),
            language=current_locale(),
        )
    except service.LimitReached:
        errors.add("email", _("Too many confirmation emails were sent today: try again tomorrow"))
        return _form(request, values, errors, status_code=429)
    masked = mask_email(email)
    if subscribed.confirmation_sent:
        notice = _("We sent a link to %(address)s. Open it to start the reminders for %(plate)s.") % {
            "address": masked,
            "plate": vehicle.registration_number,
        }
    else:
        notice = _("Reminders for %(plate)s already go to %(address)s.") % {
            "plate": vehicle.registration_number,
            "address": masked,
        }
    return render(request, "notifications/done.html", {"heading": _("Check your email"), "notice": notice})


@router.get("/reminders/confirm/{token}")
def reminders_confirm(request: Request, session: SessionDep, token: TOKEN) -> Response:
    """The link in the confirmation email: the reminders start."""
    subscription = service.confirm_link(session, token)
    if subscription is None:
        return render(
            request,
            "notifications/done.html",
            {
                "heading": _("This link does not work"),
                "notice": _("It was used to unsubscribe, or it is mistyped."),
            },
            status_code=404,
        )
    plate = service.vehicle_of(session, subscription)
    notice = _(
        "You will get an email 30 and 7 days before the certificate of %(plate)s expires, and a day after. "
        "Every email has a link to stop them."
    ) % {"plate": plate}
    return render(request, "notifications/done.html", {"heading": _("Reminders confirmed"), "notice": notice})


@router.get("/reminders/unsubscribe/{token}")
def unsubscribe_page(request: Request, session: SessionDep, token: TOKEN) -> Response:
    """The link in every email: one button stops the reminders (a link checker opening it stops nothing)."""
    known = session.scalar(select(Subscription.id).where(Subscription.token == token)) is not None
    return render(
        request,
        "notifications/unsubscribe.html",
        {"token": token, "known": known},
        status_code=200 if known else 404,
    )


@router.post("/reminders/unsubscribe/{token}")
def unsubscribe(request: Request, session: SessionDep, token: TOKEN) -> Response:
    """Stop the reminders: the subscription and its contact deleted. Also a mail program's one-click
    POST (RFC 8058, List-Unsubscribe-Post), which carries no cookie: the link's secret is the check."""
    plate = service.unsubscribe(session, token)
    notice = (
        _("Nothing more will be sent, and your address is deleted.")
        if plate is None
        else _("No more reminders about %(plate)s will be sent, and your address is deleted.")
        % {"plate": plate}
    )
    return render(request, "notifications/done.html", {"heading": _("Reminders stopped"), "notice": notice})


def day_counts(session: Session, since: date) -> list[dict[str, object]]:
    """Per day from `since`, newest first: subscriptions confirmed and ended, messages sent and failed."""
    rows = session.execute(
        select(NotificationDay.day, NotificationDay.what, NotificationDay.count).where(
            NotificationDay.day >= since
        )
    ).all()
    days: dict[date, dict[str, object]] = {}
    for day, what, count in rows:
        days.setdefault(day, {"day": day, "subscribed": 0, "unsubscribed": 0, "sent": 0, "failed": 0})[
            what
        ] = count
    return [days[day] for day in sorted(days, reverse=True)]


@router.get("/admin/reminders")
def admin_counts(request: Request, session: SessionDep, login: AdminLogin) -> Response:
    """Counts only: subscriptions, messages waiting, sent and failed, by day."""
    del login
    confirmed = session.scalar(select(func.count()).where(Subscription.confirmed_at.is_not(None)))
    pending = session.scalar(select(func.count()).where(Subscription.confirmed_at.is_(None)))
    waiting = session.scalar(
        select(func.count()).where(OutboxMessage.sent_at.is_(None), OutboxMessage.failed_at.is_(None))
    )
    since = local_today() - timedelta(days=30)
    return render(
        request,
        "notifications/admin.html",
        {
            "confirmed": confirmed or 0,
            "pending": pending or 0,
            "waiting": waiting or 0,
            "days": day_counts(session, since),
            "now": utcnow(),
        },
    )
