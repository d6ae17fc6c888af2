"""The words of every message sent: confirmations and reminders, from the verify page's functions,
each SMS within one message (sms_text.py)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from babel.dates import format_date

from app.certificates.models import Certificate
from app.certificates.wording import lapsed_sentence, until_sentence
from app.i18n.active import current_locale
from app.i18n.active import gettext as _
from app.i18n.locales import ENGLISH
from app.notifications.sms_text import first_fitting
from app.web.formatting import long_date, to_local
from app.wording import document_kind, status_headline_on

STAGE_DAYS = {"reminder_30": 30, "reminder_7": 7}


@dataclass(frozen=True)
class Text:
    """A message's subject (email only) and body."""

    subject: str | None
    body: str


def short_date(moment: datetime) -> str:
    """A date as `long_date` words it, the month cut to three letters: 1 Dec 2027."""
    local = to_local(moment)
    if current_locale() == ENGLISH:
        return f"{local.day} {local:%b %Y}"
    return format_date(local.date(), "d MMM y", locale=current_locale())


def confirm_sms(plate: str, code: str) -> Text:
    """The code a phone confirms its reminders with."""
    return Text(
        None,
        first_fitting(
            [
                _(
                    "trikecert code %(code)s. Reply YES %(code)s to be reminded before the certificate of "
                    "%(plate)s expires. Did not ask? Ignore this."
                )
                % {"code": code, "plate": plate},
                _("trikecert code %(code)s. Reply YES %(code)s for reminders about %(plate)s.")
                % {"code": code, "plate": plate},
            ]
        ),
    )


def confirm_email(plate: str, link: str) -> Text:
    """The link an email address confirms its reminders with."""
    return Text(
        _("Confirm reminders for %(plate)s") % {"plate": plate},
        _(
            "Someone asked for reminders before the certificate of %(plate)s expires to be sent to this "
            "address."
        )
        % {"plate": plate}
        + "\n\n"
        + _("To confirm, open this link:")
        + f"\n{link}\n\n"
        + _("If it was not you, ignore this email: nothing more will be sent.")
        + "\n",
    )


def reminder_sentences(stage: str, certificate: Certificate, short: bool = False) -> list[str]:
    """A reminder's sentences: the plate and what its certificate does when, then what to do."""
    words = short_date if short else long_date
    plate = certificate.registration_number
    kind = certificate.kind
    number = f"{document_kind(kind).capitalize()} {certificate.number}"
    if stage == "reminder_after":
        headline = status_headline_on(kind, "expired", words(certificate.expires_at))
        return [f"{plate}: {number} {headline}.", lapsed_sentence(kind, "expired")]
    days = STAGE_DAYS[stage]
    return [
        _("%(plate)s: %(document)s runs out in %(days)d days.")
        % {"plate": plate, "document": number, "days": days},
        until_sentence(kind, words(certificate.expires_at)),
        _("Weigh the keke again before then."),
    ]


def reminder_sms(stage: str, certificate: Certificate) -> Text:
    """A reminder as one SMS, with how to stop them."""
    candidates = [
        " ".join([*reminder_sentences(stage, certificate, short), _("Reply STOP to end.")])
        for short in (False, True)
    ]
    return Text(None, first_fitting(candidates))


def reminder_email(stage: str, certificate: Certificate, verify_url: str, unsubscribe_url: str) -> Text:
    """A reminder by email, with the verify page and the one-click unsubscribe link."""
    sentences = reminder_sentences(stage, certificate)
    subject = sentences[0].rstrip(".")
    body = (
        " ".join(sentences)
        + "\n\n"
        + _("Check it at any time: %(url)s") % {"url": verify_url}
        + "\n\n"
        + _("To stop these reminders, open this link: %(url)s") % {"url": unsubscribe_url}
        + "\n"
    )
    return Text(subject, body)
