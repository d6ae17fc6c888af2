"""The outside world of the reminders, on localhost: a real SMTP server (aiosmtpd) and an HTTP server
that speaks Africa's Talking's send API. Both can be told to fail."""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from email import message_from_bytes, policy
from email.message import EmailMessage
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any
from urllib.parse import parse_qs

import pytest
from aiosmtpd.controller import Controller
from aiosmtpd.smtp import SMTP, Envelope, Session
from served import free_port

from app import config
from app.gateway.africastalking import AfricasTalkingSender
from app.notifications.worker import Sender, SmtpSender


@dataclass
class Mailbox:
    """What the SMTP server received; `refuse` answers the next DATA with that reply instead."""

    messages: list[EmailMessage] = field(default_factory=list)
    refuse: list[str] = field(default_factory=list)

    async def handle_DATA(self, server: SMTP, session: Session, envelope: Envelope) -> str:
        """Keep the message, or refuse it as told."""
        if self.refuse:
            return self.refuse.pop(0)
        content = envelope.original_content or b""
        parsed = message_from_bytes(content, policy=policy.default)
        assert isinstance(parsed, EmailMessage)
        self.messages.append(parsed)
        return "250 OK"

    def to(self, address: str) -> list[EmailMessage]:
        """The messages received for one address, oldest first."""
        return [message for message in self.messages if message["To"] == address]


@contextmanager
def smtp_server() -> Iterator[tuple[str, Mailbox]]:
    """A running SMTP server: its smtp:// address and its mailbox."""
    mailbox = Mailbox()
    port = free_port()
    controller = Controller(mailbox, hostname="127.0.0.1", port=port)
    controller.start()
    try:
        yield f"smtp://127.0.0.1:{port}", mailbox
    finally:
        controller.stop()


@dataclass
class Gateway:
    """What the send API received, and how it answers the next requests: 'ok', '500', 'timeout'
    (answers after `slow` seconds), 'drop' (closes the connection), 'hang' (holds the request for
    `slow` seconds, then answers ok), 'refused' (a permanent per-number status)."""

    received: list[dict[str, Any]] = field(default_factory=list)
    modes: list[str] = field(default_factory=list)
    slow: float = 5.0
    delay: float = 0.0  # before every answer: two workers' sends overlap
    lock: threading.Lock = field(default_factory=threading.Lock)
    arrived: threading.Event = field(default_factory=threading.Event)

    def next_mode(self) -> str:
        with self.lock:
            return self.modes.pop(0) if self.modes else "ok"

    def bodies(self) -> list[str]:
        """The messages received, oldest first."""
        with self.lock:
            return [request["message"] for request in self.received]


def _handler(gateway: Gateway) -> type[BaseHTTPRequestHandler]:
    class SendApi(BaseHTTPRequestHandler):
        def log_message(self, format: str, *args: Any) -> None:
            """Quiet."""

        def do_POST(self) -> None:
            if self.path != "/version1/messaging":
                self.send_error(404)
                return
            length = int(self.headers.get("Content-Length", "0"))
            fields = {key: values[0] for key, values in parse_qs(self.rfile.read(length).decode()).items()}
            mode = gateway.next_mode()
            if mode == "drop":
                self.connection.close()
                return
            if mode == "500":
                self.send_error(500)
                return
            if mode in ("timeout", "hang"):
                with gateway.lock:
                    gateway.received.append({**fields, "apiKey": self.headers.get("apiKey"), "mode": mode})
                gateway.arrived.set()
                time.sleep(gateway.slow)
                if mode == "timeout":
                    return
            else:
                with gateway.lock:
                    gateway.received.append({**fields, "apiKey": self.headers.get("apiKey"), "mode": mode})
                gateway.arrived.set()
                time.sleep(gateway.delay)
            status = (403, "InvalidPhoneNumber") if mode == "refused" else (101, "Success")
            body = json.dumps(
                {
                    "SMSMessageData": {
                        "Message": "Sent to 1/1 Total Cost: NGN 2.2000",
                        "Recipients": [
                            {
                                "statusCode": status[0],
                                "number": fields.get("to"),
                                "status": status[1],
                                "cost": "NGN 2.2000",
                                "messageId": f"ATXid_{len(gateway.received)}",
                            }
                        ],
                    }
                }
            ).encode()
            try:
                self.send_response(201)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)
            except OSError:
                pass  # the worker hung up (a timeout)

    return SendApi


@contextmanager
def send_api() -> Iterator[tuple[str, Gateway]]:
    """A running send API: its base address and what it received."""
    gateway = Gateway()
    server = ThreadingHTTPServer(("127.0.0.1", free_port()), _handler(gateway))
    server.daemon_threads = True
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}", gateway
    finally:
        server.shutdown()
        server.server_close()


@contextmanager
def outside_services(monkeypatch: pytest.MonkeyPatch, **settings: str) -> Iterator[tuple[Mailbox, Gateway]]:
    """The mail server and the SMS gateway, running, and the settings pointing at them (and `settings`)."""
    with smtp_server() as (smtp_url, mailbox), send_api() as (base, gateway):
        environment = {
            "TRIKECERT_SMTP_URL": smtp_url,
            "TRIKECERT_AFRICASTALKING_BASE_URL": base,
            "TRIKECERT_AFRICASTALKING_API_KEY": "at-test-key",
            "TRIKECERT_NOTIFY_TIMEOUT_SECONDS": "1",
            **settings,
        }
        for name, value in environment.items():
            monkeypatch.setenv(name, value)
        config.get_settings.cache_clear()
        try:
            yield mailbox, gateway
        finally:
            config.get_settings.cache_clear()


def senders(smtp_timeout: float) -> dict[str, Sender]:
    """The worker's senders, by channel, for the settings in force."""
    settings = config.get_settings()
    assert settings.smtp_url is not None
    return {
        "email": SmtpSender(settings.smtp_url.get_secret_value(), settings.mail_from, smtp_timeout),
        "sms": AfricasTalkingSender(settings),
    }
