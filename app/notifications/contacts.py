"""Phone numbers and email addresses: normalised (E.164, lower-case domain), masked wherever shown,
and digested where only their sameness matters (limits, counts)."""

from __future__ import annotations

import hashlib
import hmac
import re

from app.config import get_settings
from app.notifications.digest_key import contact_digest_key
from app.text import TextRefused, check_text

EMAIL_LENGTH = 254
_EMAIL = re.compile(
    r"[A-Za-z0-9!#$%&'*+/=?^_`{|}~.\-]{1,64}@[A-Za-z0-9](?:[A-Za-z0-9\-]{0,62}\.)+[A-Za-z]{2,63}"
)
_DIGITS = re.compile(r"\d+")


class ContactRefused(ValueError):
    """A text that is no phone number or email address, with the rule it breaks."""

    def __init__(self, message: str, rule: str) -> None:
        super().__init__(message)
        self.rule = rule


def normalise_phone(raw: str, country_code: str = "234") -> str:
    """E.164: '+2348012345667' from '+234 801 234 5667', '08012345667' or '2348012345667'."""
    text = raw.strip()
    cleaned = re.sub(r"[\s\-().]", "", text)
    if cleaned.startswith("00"):
        cleaned = "+" + cleaned[2:]
    if not cleaned.isascii() or not _DIGITS.fullmatch(cleaned.lstrip("+")):
        raise ContactRefused("a phone number has digits only, like +234 801 234 5667", "format")
    if cleaned.startswith("+"):
        digits = cleaned[1:]
    elif cleaned.startswith("0"):
        digits = country_code + cleaned[1:]
    else:
        digits = cleaned
    if not 8 <= len(digits) <= 15 or digits.startswith("0"):
        raise ContactRefused("a phone number has 8 to 15 digits with its country code", "format")
    return f"+{digits}"


def normalise_email(raw: str) -> str:
    """The address with its domain in lower case; ContactRefused when it is not one."""
    try:
        text = check_text(raw, max_length=EMAIL_LENGTH).strip()
    except TextRefused as refused:
        raise ContactRefused(str(refused), "text") from refused
    if not _EMAIL.fullmatch(text):
        raise ContactRefused("an email address looks like name@example.com", "format")
    local, domain = text.rsplit("@", 1)
    return f"{local}@{domain.lower()}"


def mask_phone(phone: str) -> str:
    """'+234 80• ••• ••67': the country code, two digits and the last two; the rest hidden."""
    digits = phone.lstrip("+")
    code = digits[:3] if digits.startswith("234") else digits[: max(1, len(digits) - 10)]
    rest = digits[len(code) :]
    shown = rest[:2] + "•" * max(0, len(rest) - 4) + rest[-2:]
    groups = [shown[:3], shown[3:6], shown[6:]]
    return f"+{code} " + " ".join(group for group in groups if group)


def mask_email(email: str) -> str:
    """'j•••@example.com': the first letter and the domain."""
    local, _, domain = email.partition("@")
    return f"{local[:1]}•••@{domain}"


def mask(channel: str, contact: str) -> str:
    """A contact as every page and log line shows it."""
    return mask_phone(contact) if channel == "sms" else mask_email(contact)


def digest(value: str) -> str:
    """A contact or client address as only its sameness is kept (limits and counts): keyed, so that
    the digest of a phone number cannot be found by hashing every number (app/notifications/digest_key.py)."""
    key = contact_digest_key(get_settings())
    return hmac.new(key, f"trikecert-contact:{value}".encode(), hashlib.sha256).hexdigest()
