"""A fake trikecert on a raw socket, in a thread: each connection gets the next act of a script, so a
test can make the network do to the station client whatever a real one does (refuse, reset, cut an
answer short, stay silent, answer 5xx, 408, 409 or 429) and then store the weighing once."""

from __future__ import annotations

import contextlib
import json
import socket
import struct
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Request:
    """One request as the fake received it (the headers it had read when it acted)."""

    idempotency_key: str | None
    body: bytes
    received_at: float  # time.monotonic(), the clock the client's sleeps run on too


@dataclass
class FakeStationService:
    """Listens on 127.0.0.1; `listen()` starts answering (until then a connection is refused)."""

    script: list[Act]
    requests: list[Request] = field(default_factory=list)
    stored: dict[str, int] = field(default_factory=dict)  # Idempotency-Key -> inspection id
    sending_at: dict[int, float] = field(default_factory=dict)  # request index -> its answer began
    errors: list[BaseException] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.listener = socket.socket()
        self.listener.bind(("127.0.0.1", 0))  # bound, not listening: connecting is refused
        self.thread = threading.Thread(target=self._serve, daemon=True)

    @property
    def url(self) -> str:
        """The base address."""
        return f"http://127.0.0.1:{self.listener.getsockname()[1]}"

    def listen(self) -> None:
        """Start accepting connections, one act each."""
        self.listener.listen(8)
        self.thread.start()

    def close(self) -> None:
        """Stop listening (a pending accept ends too) and report any act that went wrong."""
        with contextlib.suppress(OSError):
            self.listener.shutdown(socket.SHUT_RDWR)
        self.listener.close()
        if self.thread.is_alive():
            self.thread.join(timeout=30)
        if self.errors:
            raise self.errors[0]

    def _serve(self) -> None:
        for act in self.script:
            try:
                connection, _ = self.listener.accept()
            except OSError:
                return
            try:
                with connection:
                    connection.settimeout(30)
                    act(connection, self)
            except BaseException as error:  # reported to the test by close()
                self.errors.append(error)

    def send(self, connection: socket.socket, data: bytes) -> None:
        """Send (part of) an answer, noting when it began: the client's wait is measured from here."""
        self.sending_at[len(self.requests) - 1] = time.monotonic()
        connection.sendall(data)

    def store(self, key: str | None) -> tuple[int, bool]:
        """The inspection id for this key, stored once; and whether it had been stored before."""
        assert key, "the client sent no Idempotency-Key"
        if key in self.stored:
            return self.stored[key], True
        self.stored[key] = 100 + len(self.stored)
        return self.stored[key], False


Act = Callable[[socket.socket, FakeStationService], None]


def _read_head(connection: socket.socket) -> tuple[dict[str, str], bytes]:
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = connection.recv(65536)
        if not chunk:
            raise AssertionError("the client closed before sending a whole request")
        data += chunk
    head, rest = data.split(b"\r\n\r\n", 1)
    lines = head.decode("latin-1").split("\r\n")
    headers = {k.strip().lower(): v.strip() for k, v in (line.split(":", 1) for line in lines[1:])}
    return headers, rest


def read_request(connection: socket.socket, service: FakeStationService) -> Request:
    """Read one whole request and record it."""
    headers, body = _read_head(connection)
    while len(body) < int(headers.get("content-length", "0")):
        chunk = connection.recv(65536)
        if not chunk:
            break
        body += chunk
    request = Request(headers.get("idempotency-key"), body, time.monotonic())
    service.requests.append(request)
    return request


def _answer(status: str, headers: dict[str, str], body: bytes, *, length: int | None = None) -> bytes:
    lines = [f"HTTP/1.1 {status}", f"Content-Length: {len(body) if length is None else length}"]
    lines += [f"{k}: {v}" for k, v in headers.items()] + ["Connection: close", "", ""]
    return "\r\n".join(lines).encode() + body


def answer(status: str, body: bytes, headers: dict[str, str] | None = None) -> Act:
    """A whole answer, as the service (or a proxy in front of it) might give."""

    def act(connection: socket.socket, service: FakeStationService) -> None:
        read_request(connection, service)
        service.send(connection, _answer(status, headers or {}, body))

    return act


def refusal(status: str, detail: str, headers: dict[str, str] | None = None) -> Act:
    """The service's JSON error answer."""
    body = json.dumps({"detail": detail, "errors": []}).encode()
    return answer(status, body, {"Content-Type": "application/json", **(headers or {})})


def created(*, cut_after: int | None = None) -> Act:
    """Store the weighing (once per key) and answer 201, replayed when stored before; with
    `cut_after`, the connection drops after that many bytes of the body (stored, answer lost)."""

    def act(connection: socket.socket, service: FakeStationService) -> None:
        request = read_request(connection, service)
        inspection_id, replayed = service.store(request.idempotency_key)
        body = json.dumps({"id": inspection_id, "registration_number": "BDG 252 QH"}).encode()
        headers = {"Content-Type": "application/json"} | ({"Idempotent-Replayed": "true"} if replayed else {})
        whole = _answer("201 Created", headers, body)
        service.send(connection, whole if cut_after is None else whole[: len(whole) - len(body) + cut_after])

    return act


def cut_off(status: str, detail: str) -> Act:
    """A status line and headers promising a body that stops part-way (the service died sending it)."""
    body = json.dumps({"detail": detail, "errors": []}).encode()

    def act(connection: socket.socket, service: FakeStationService) -> None:
        read_request(connection, service)
        service.send(
            connection, _answer(status, {"Content-Type": "application/json"}, body[:9], length=len(body))
        )

    return act


def reset_mid_request(connection: socket.socket, service: FakeStationService) -> None:
    """Read the request's head, then reset the connection (RST) before answering."""
    headers, _ = _read_head(connection)
    service.requests.append(Request(headers.get("idempotency-key"), b"", time.monotonic()))
    connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))


def silent(connection: socket.socket, service: FakeStationService) -> None:
    """Read the request and say nothing until the client gives up waiting and closes."""
    read_request(connection, service)
    while connection.recv(65536):
        pass


def stalls_mid_answer(connection: socket.socket, service: FakeStationService) -> None:
    """Send the status line and headers of a 201, then nothing more until the client gives up."""
    read_request(connection, service)
    service.send(connection, _answer("201 Created", {"Content-Type": "application/json"}, b"", length=64))
    while connection.recv(65536):
        pass
