"""The words of every message sent: confirmations and reminders, from the verify page's functions,
each SMS within one message (sms_text.py)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from app.certificates.models import Certificate
from app.certificates.wording import lapsed_sentence, until_sentence
from app.notifications.sms_text import first_fitting
from app.web.formatting import long_date, to_local
from app.wording import document_kind, status_headline_on

STOP_HINT = "Reply STOP to end."
STAGE_DAYS = {"reminder_30": 30, "reminder_7": 7}


@dataclass(frozen=True)
class Text:
    """A message's subject (email only) and body."""

    subject: str | None
    body: str


def short_date(moment: datetime) -> str:
    """A date as `long_date` words it, the month cut to three letters: 1 Dec 2027."""
    local = to_local(moment)
    return f"{local.day} {local:%b %Y}"


def confirm_sms(plate: str, code: str) -> Text:
    """The code a phone confirms its reminders with."""
    return Text(
        None,
        first_fitting(
            [
                f"trikecert code {code}. Reply YES {code} to be reminded before the certificate of {plate} "
                "expires. Did not ask? Ignore this.",
                f"trikecert code {code}. Reply YES {code} for reminders about {plate}.",
            ]
        ),
    )


def confirm_email(plate: str, link: str) -> Text:
    """The link an email address confirms its reminders with."""
    return Text(
        f"Confirm reminders for {plate}",
        f"Someone asked for reminders before the certificate of {plate} expires to be sent to this "
        f"address.\n\nTo confirm, open this link:\n{link}\n\nIf it was not you, ignore this email: "
        "nothing more will be sent.\n",
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
        f"{plate}: {number} runs out in {days} days.",
        until_sentence(kind, words(certificate.expires_at)),
        "Weigh the keke again before then.",
    ]


def reminder_sms(stage: str, certificate: Certificate) -> Text:
    """A reminder as one SMS, with how to stop them."""
    candidates = [
        " ".join([*reminder_sentences(stage, certificate, short), STOP_HINT]) for short in (False, True)
    ]
    return Text(None, first_fitting(candidates))


def reminder_email(stage: str, certificate: Certificate, verify_url: str, unsubscribe_url: str) -> Text:
    """A reminder by email, with the verify page and the one-click unsubscribe link."""
    sentences = reminder_sentences(stage, certificate)
    subject = sentences[0].rstrip(".")
    body = (
        " ".join(sentences)
        + f"\n\nCheck it at any time: {verify_url}\n\n"
        + f"To stop these reminders, open this link: {unsubscribe_url}\n"
    )
    return Text(subject, body)
