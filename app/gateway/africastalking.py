"""Africa's Talking: the USSD and incoming-SMS callbacks it posts, and its SMS send API.

Its formats (https://developers.africastalking.com): a USSD callback posts `sessionId`,
`serviceCode`, `phoneNumber` and `text` (the choices so far joined by '*') and takes `text/plain`
starting "CON " (more to come) or "END "; an incoming SMS posts `from`, `to`, `text`, `date`, `id`
and `linkId`, answered 200; the send API takes `POST {base}/version1/messaging` with the form
fields `username`, `to`, `message` and `from`, and the header `apiKey`.
"""

from __future__ import annotations

import json
import urllib.error
import urllib.request
from typing import Annotated
from urllib.parse import urlencode

from fastapi import APIRouter, Depends, Form
from fastapi.responses import PlainTextResponse, Response
from sqlalchemy.exc import IntegrityError

from app.config import Settings, get_settings
from app.db import utcnow
from app.gateway import conversation
from app.gateway.access import callback_allowed
from app.notifications.models import OutboxMessage
from app.notifications.worker import SendFailed
from app.web.deps import SessionDep

router = APIRouter(
    prefix="/gateway/africastalking", include_in_schema=False, dependencies=[Depends(callback_allowed)]
)

FIELD = 100  # the longest id, code or number a callback's field may hold
PRINTABLE = r"^[^\x00-\x1f\x7f]*$"  # an id, code or number: no control character (PostgreSQL takes no NUL)
TEXT = 20_000  # a USSD or SMS text beyond this is refused (422); below it, answered


@router.post("/ussd")
def ussd_callback(
    session: SessionDep,
    session_id: Annotated[str, Form(alias="sessionId", max_length=FIELD, pattern=PRINTABLE)],
    service_code: Annotated[str, Form(alias="serviceCode", max_length=FIELD, pattern=PRINTABLE)],
    phone_number: Annotated[str, Form(alias="phoneNumber", max_length=FIELD, pattern=PRINTABLE)],
    text: Annotated[str, Form(max_length=TEXT)] = "",
) -> Response:
    """One step of a USSD session: the next screen, 'CON ...' or 'END ...'."""
    del session_id, service_code  # the whole path so far comes in `text`: no session is kept
    try:
        screen = conversation.ussd(session, phone_number, text, get_settings(), utcnow())
    except IntegrityError:  # the same request twice at once: the other one did it
        session.rollback()
        screen = conversation.Screen(
            "This was asked twice at once: dial again to see where it stands.", more=False
        )
    return PlainTextResponse(screen.wire())


@router.post("/sms")
def sms_callback(
    session: SessionDep,
    sender: Annotated[str, Form(alias="from", max_length=FIELD, pattern=PRINTABLE)],
    to: Annotated[str, Form(max_length=FIELD, pattern=PRINTABLE)],
    text: Annotated[str, Form(max_length=TEXT)],
    message_id: Annotated[str, Form(alias="id", min_length=1, max_length=FIELD, pattern=PRINTABLE)],
    date: Annotated[str, Form(max_length=FIELD, pattern=PRINTABLE)] = "",
    link_id: Annotated[str, Form(alias="linkId", max_length=FIELD, pattern=PRINTABLE)] = "",
) -> Response:
    """An incoming SMS: its reply goes into the outbox (the worker sends it); the gateway gets 200."""
    del to, date, link_id
    try:
        conversation.sms(session, sender, text, message_id, get_settings(), utcnow())
    except IntegrityError:  # the same message posted twice at once: the other one answers it
        session.rollback()
    return PlainTextResponse("OK")


# Per recipient: 100 Processed, 101 Sent, 102 Queued; these others may pass on a later try.
_SENT = {100, 101, 102}
_TRANSIENT = {405, 500, 501}  # insufficient balance, the gateway's own errors


class AfricasTalkingSender:
    """Sends an outbox SMS through the send API; SendFailed says whether trying again may help."""

    def __init__(self, settings: Settings) -> None:
        self.url = f"{settings.africastalking_base_url.rstrip('/')}/version1/messaging"
        self.username = settings.africastalking_username
        key = settings.africastalking_api_key
        self.api_key = key.get_secret_value() if key is not None else ""
        self.sender = settings.africastalking_sender
        self.timeout = settings.notify_timeout_seconds

    def send(self, message: OutboxMessage) -> str | None:
        """Post the message; the gateway's message id."""
        fields = {"username": self.username, "to": message.recipient or "", "message": message.body}
        if self.sender:
            fields["from"] = self.sender
        request = urllib.request.Request(  # noqa: S310 (the address is a setting, http or https)
            self.url,
            data=urlencode(fields).encode(),
            headers={
                "apiKey": self.api_key,
                "Accept": "application/json",
                "Content-Type": "application/x-www-form-urlencoded",
            },
            method="POST",
        )
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as response:  # noqa: S310
                body = response.read(65536)
        except urllib.error.HTTPError as error:
            status = error.code
            permanent = status < 500 and status not in (408, 429)
            raise SendFailed(f"gateway answered {status}", permanent=permanent) from None
        except (urllib.error.URLError, TimeoutError, ConnectionError, OSError) as error:
            raise SendFailed(f"gateway unreachable: {type(error).__name__}", permanent=False) from None
        return _outcome(body)


def _outcome(body: bytes) -> str | None:
    """The message id of the one recipient, or SendFailed from its status code."""
    try:
        recipients = json.loads(body)["SMSMessageData"]["Recipients"]
        recipient = recipients[0]
        code = int(recipient["statusCode"])
    except (ValueError, KeyError, IndexError, TypeError):
        raise SendFailed("gateway's answer unreadable", permanent=False) from None
    if code in _SENT:
        message_id = recipient.get("messageId")
        return str(message_id)[:120] if message_id else None
    raise SendFailed(
        f"gateway refused: {code} {str(recipient.get('status', ''))[:60]}", permanent=code not in _TRANSIENT
    )
