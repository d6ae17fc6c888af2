"""The verification's facts in words and codes, one function each: the public status a machine reads,
the QR check as the verify page says it, and why a typed number finds no document.

The JSON verification, the verify page and `trikecert verify` all take their status from here, so a
refusal or a revoked certificate can never read as certified in one of them and not in another.
"""

from __future__ import annotations

from typing import Literal

from app.i18n.active import gettext as _
from app.wording import QR_NOT_GENUINE
from app.wording import status_meaning as status_meaning  # the offline check (app/trust) says it too

PublicStatus = Literal["certified", "refused", "revoked", "superseded", "expired"]
QrTone = Literal["genuine", "forged", "refused", "revoked", "lapsed"]
NumberRule = Literal["format", "check_letter", "exists"]


def public_status(kind: str, status: str) -> PublicStatus:
    """What a document means now: certified or refused while it stands, else revoked, superseded, expired."""
    if status == "issued":
        return "certified" if kind == "compliant" else "refused"
    if status == "revoked":
        return "revoked"
    if status == "superseded":
        return "superseded"
    return "expired"


def in_force(status: PublicStatus) -> bool:
    """True only for a certificate that certifies the vehicle now; a refusal certifies nothing."""
    return status == "certified"


def public_kind(kind: str) -> Literal["certificate", "refusal"]:
    """The document's kind as the public verification and the signed payload name it."""
    return "certificate" if kind == "compliant" else "refusal"


def qr_tone(status: PublicStatus, genuine: bool) -> QrTone:
    """The QR check box's colour: green only for a genuine code on a certificate in force."""
    if not genuine:
        return "forged"
    if status == "certified":
        return "genuine"
    if status in ("refused", "revoked"):
        return status
    return "lapsed"


def qr_title(kind: str, status: PublicStatus, genuine: bool) -> str:
    """The QR check box's title: genuine, genuine but not in force (and why), or NOT genuine."""
    if not genuine:
        return _(QR_NOT_GENUINE)
    if status == "certified":
        return _("The QR code is genuine")
    if status == "refused":
        return _("The QR code is genuine, but this paper is a REFUSAL")
    certificate = kind == "compliant"
    if status == "expired":
        if certificate:
            return _("The QR code is genuine, but this certificate has EXPIRED")
        return _("The QR code is genuine, but this refusal has EXPIRED")
    if status == "revoked":
        if certificate:
            return _("The QR code is genuine, but this certificate was REVOKED")
        return _("The QR code is genuine, but this refusal was REVOKED")
    if certificate:
        return _("The QR code is genuine, but this certificate was SUPERSEDED")
    return _("The QR code is genuine, but this refusal was SUPERSEDED")


def qr_explanation(status: PublicStatus) -> str:
    """What a genuine QR code vouches for, said so that it cannot be read as more than it is."""
    if status == "certified":
        return _(
            "It was signed by the issuing authority and matches this record. "
            "The banner above says what the paper means."
        )
    if status == "refused":
        return _(
            "It was signed by the issuing authority and matches this record, but a refusal certifies nothing."
        )
    return _(
        "It was signed by the issuing authority and matches this record, but the paper no longer counts."
    )


def not_on_record(number: str) -> str:
    """Why a well-formed number finds nothing, as the verify page, its form and the API say it."""
    return _(
        "no certificate or refusal %(number)s is on record: a paper that shows this number is not valid"
    ) % {"number": number}


def number_headline(rule: NumberRule) -> str:
    """The red banner's headline for a number that finds no document."""
    if rule == "exists":
        return _("NOT VALID: no certificate has this number")
    if rule == "check_letter":
        return _("NOT VALID: the number is mistyped")
    return _("NOT VALID: this is not a certificate number")


def sentence(message: str) -> str:
    """A message as a sentence on a page: its first letter in capitals, a full stop at the end."""
    text = message[:1].upper() + message[1:]
    return text if text.endswith(".") else f"{text}."


def until_sentence(kind: str, until: str) -> str:
    """How long a standing document counts: 'Valid until 1 December 2027.' (a refusal: 'stands until')."""
    if kind == "compliant":
        return _("Valid until %(date)s.") % {"date": until}
    return _("This refusal stands until %(date)s.") % {"date": until}


def lapsed_sentence(kind: str, status: str) -> str:
    """What a revoked, expired or replaced document still means: 'This certificate was withdrawn: ...'."""
    certificate = kind == "compliant"
    if status == "revoked":
        if certificate:
            return _("This certificate was withdrawn: it certifies nothing.")
        return _("This refusal was withdrawn: it certifies nothing.")
    if status == "expired":
        if certificate:
            return _("This certificate no longer counts: the vehicle must be weighed again.")
        return _("This refusal no longer counts: the vehicle must be weighed again.")
    if certificate:
        return _("This certificate was replaced and no longer counts.")
    return _("This refusal was replaced and no longer counts.")
