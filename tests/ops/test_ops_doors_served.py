"""Limits on the doors of a served process (`trikecert serve`, the guarded uvicorn protocol):
slow clients are cut off at the documented deadlines, normal ones are not; the public verification
is limited per client address, the address a trusted proxy forwards."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
from served import free_port, wait_until_ready

BIN = Path(sys.executable).parent
# Short deadlines (the settings take fractions of a second), and a client's bytes a quarter of the
# headers' deadline apart: a timer that each byte restarted would never fire, so only a deadline for
# the whole part cuts the client off.
HEADER_TIMEOUT = 1
BODY_TIMEOUT = 1.5
PACE = HEADER_TIMEOUT / 4  # seconds between two trickled bytes
EARLY = 0.9  # a cut-off before this share of its deadline is too early
PUBLIC_LIMIT = 5
PUBLIC_WINDOW = 3600  # long, and a test never starts near its turn (the_window_holds_still)


# `trikecert serve` runs the guarded protocol on the parser uvicorn picks (httptools, installed here);
# the same guard on h11, uvicorn's pure-Python parser, is served by uvicorn's own command.
H11 = [
    "-m",
    "uvicorn",
    "--factory",
    "app.main:create_served_app",
    "--http",
    "app.ops.slow_clients:GuardedH11Protocol",
    "--proxy-headers",
    "--forwarded-allow-ips",
    "127.0.0.1",
]


@pytest.fixture(scope="module", params=["serve", "h11"])
def served(request: pytest.FixtureRequest, database_url: str) -> Iterator[int]:
    """The service (one worker: one process counts every request) with short deadlines; its port."""
    env = dict(
        os.environ,
        TRIKECERT_DATABASE_URL=database_url,
        TRIKECERT_HEADER_TIMEOUT_SECONDS=str(HEADER_TIMEOUT),
        TRIKECERT_BODY_TIMEOUT_SECONDS=str(BODY_TIMEOUT),
        TRIKECERT_PUBLIC_RATE_LIMIT=str(PUBLIC_LIMIT),
        TRIKECERT_PUBLIC_RATE_WINDOW_SECONDS=str(PUBLIC_WINDOW),
        TRIKECERT_FORWARDED_ALLOW_IPS="127.0.0.1",  # the test plays the proxy
    )
    port = free_port()
    command = (
        [BIN / "trikecert", "serve", "--workers", "1"]
        if request.param == "serve"
        else [sys.executable, *H11, "--log-level", "warning"]
    )
    server = subprocess.Popen(
        [*command, "--port", str(port)],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        wait_until_ready(f"http://127.0.0.1:{port}/readyz", server)
        yield port
    finally:
        server.terminate()
        server.wait(timeout=30)


def trickle(port: int, sent_whole: bytes, trickled: bytes) -> tuple[bytes, float, int]:
    """Send `sent_whole` at once, then `trickled` one byte every PACE seconds until the server answers
    or closes; the answer, the seconds from the connection's opening and the bytes trickled."""
    with socket.create_connection(("127.0.0.1", port)) as sock:
        started = time.monotonic()
        sock.settimeout(PACE)
        if sent_whole:
            sock.sendall(sent_whole)
        answer, count = b"", 0
        for byte in trickled:
            try:
                sock.sendall(bytes([byte]))
                count += 1
                chunk = sock.recv(65536)  # waits up to PACE: the client's pace
            except TimeoutError:
                continue
            except (BrokenPipeError, ConnectionResetError):
                break
            answer += chunk
            if not chunk:
                break
        sock.settimeout(5)
        try:
            while chunk := sock.recv(65536):
                answer += chunk
        except (TimeoutError, ConnectionResetError):
            pass
        return answer, time.monotonic() - started, count


def refusal_of(answer: bytes) -> dict[str, object]:
    """The JSON body of a raw HTTP answer."""
    body: dict[str, object] = json.loads(answer.split(b"\r\n\r\n", 1)[1])
    return body


def test_headers_sent_byte_by_byte_are_cut_off_at_the_deadline(served: int) -> None:
    request = b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nUser-Agent: slow\r\nAccept: */*\r\n\r\n"
    answer, seconds, sent = trickle(served, b"", request)
    assert answer.startswith(b"HTTP/1.1 408 "), answer
    assert b"connection: close" in answer
    assert EARLY * HEADER_TIMEOUT <= seconds <= HEADER_TIMEOUT + 2.5, seconds
    assert sent < len(request), "cut off before the headers were complete"
    assert refusal_of(answer)["errors"] == [
        {
            "field": "headers",
            "rule": "read_timeout",
            "message": f"headers: the request's headers did not arrive whole within {HEADER_TIMEOUT} s",
        }
    ]


def test_a_connection_that_sends_nothing_is_closed_at_the_headers_deadline(served: int) -> None:
    with socket.create_connection(("127.0.0.1", served)) as sock:
        started = time.monotonic()
        sock.settimeout(HEADER_TIMEOUT + 5)
        answer = sock.recv(65536)
        while chunk := sock.recv(65536):
            answer += chunk
        seconds = time.monotonic() - started
    assert answer.startswith(b"HTTP/1.1 408 ")
    assert EARLY * HEADER_TIMEOUT <= seconds <= HEADER_TIMEOUT + 2


def test_a_body_sent_byte_by_byte_is_cut_off_at_the_deadline(served: int) -> None:
    body = json.dumps({"registration_number": "BDG 252 QH", "readings": {}}).encode()
    head = (
        b"POST /api/v1/inspections HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
        b"Authorization: Bearer not-a-key\r\nContent-Length: " + str(len(body)).encode() + b"\r\n\r\n"
    )
    answer, seconds, sent = trickle(served, head, body)
    assert answer.startswith(b"HTTP/1.1 408 "), answer
    assert EARLY * BODY_TIMEOUT <= seconds <= BODY_TIMEOUT + 2.5, seconds
    assert sent < len(body)
    assert refusal_of(answer)["errors"] == [
        {
            "field": "body",
            "rule": "read_timeout",
            "message": f"body: the request's body did not arrive whole within {BODY_TIMEOUT} s",
        }
    ]


def test_headers_larger_than_the_limit_are_refused(served: int, request: pytest.FixtureRequest) -> None:
    padding = b"".join(b"X-Padding-%d: %s\r\n" % (n, b"a" * 1000) for n in range(40))
    with socket.create_connection(("127.0.0.1", served), timeout=5) as sock:
        sock.sendall(b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n" + padding)
        answer = b""
        while chunk := sock.recv(65536):
            answer += chunk
    if request.node.callspec.params["served"] == "h11":  # h11 refuses first, beyond its own 16 KiB
        assert answer.startswith(b"HTTP/1.1 400 ")
        return
    assert answer.startswith(b"HTTP/1.1 431 ")
    assert refusal_of(answer)["errors"] == [
        {
            "field": "headers",
            "rule": "max_size",
            "message": "headers: the request's headers are larger than 32 KiB",
        }
    ]


def read_response(sock: socket.socket) -> bytes:
    """One whole response with a content-length from a kept-alive connection."""
    data = b""
    while b"\r\n\r\n" not in data:
        data += sock.recv(65536)
    head, body = data.split(b"\r\n\r\n", 1)
    length = next(
        int(line.split(b":", 1)[1])
        for line in head.split(b"\r\n")
        if line.lower().startswith(b"content-length:")
    )
    while len(body) < length:
        body += sock.recv(65536)
    return head


def test_normal_clients_keep_their_connection_across_requests_and_pauses(served: int) -> None:
    request = b"GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
    with socket.create_connection(("127.0.0.1", served), timeout=10) as sock:
        sock.sendall(request)
        assert read_response(sock).startswith(b"HTTP/1.1 200 ")
        time.sleep(HEADER_TIMEOUT)  # idle between requests: within the keep-alive time
        sock.sendall(request[:10])  # then headers in pieces, each request within its own deadline
        # The headers end past their deadline counted from the last answer, within it from their first byte.
        time.sleep(HEADER_TIMEOUT - 0.8)
        sock.sendall(request[10:])
        assert read_response(sock).startswith(b"HTTP/1.1 200 "), "the deadline restarts for each request"
        sock.sendall(b"POST /api/v1/inspections HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 2\r\n\r\n{")
        time.sleep(BODY_TIMEOUT - 1)
        sock.sendall(b"}")
        assert read_response(sock).startswith(b"HTTP/1.1 401 "), "a body in time reaches the application"


def get(
    port: int, path: str, forwarded_for: str, accept: str = "application/json"
) -> tuple[int, dict[str, str], str]:
    """GET through the test's 'proxy' (127.0.0.1, trusted) for the client `forwarded_for`."""
    request = urllib.request.Request(
        f"http://127.0.0.1:{port}{path}", headers={"X-Forwarded-For": forwarded_for, "Accept": accept}
    )
    try:
        with urllib.request.urlopen(request, timeout=10) as response:
            return (
                response.status,
                {k.lower(): v for k, v in response.headers.items()},
                response.read().decode(),
            )
    except urllib.error.HTTPError as refused:
        return refused.code, {k.lower(): v for k, v in refused.headers.items()}, refused.read().decode()


def the_window_holds_still() -> None:
    """Wait out the turn of the public limit's fixed window if it comes within the next 10 s."""
    left = PUBLIC_WINDOW - time.time() % PUBLIC_WINDOW
    if left < 10:
        time.sleep(left + 0.5)


def test_the_public_verification_is_limited_per_forwarded_address(served: int) -> None:
    the_window_holds_still()
    numbers = [f"/api/v1/verify/TRK-2026-{n:06d}-A" for n in range(1, PUBLIC_LIMIT + 3)]
    statuses = [get(served, path, "203.0.113.9")[0] for path in numbers]
    assert 429 not in statuses[:PUBLIC_LIMIT]
    assert statuses[PUBLIC_LIMIT:] == [429, 429]

    status, headers, body = get(served, numbers[0], "203.0.113.9")
    assert status == 429
    assert 1 <= int(headers["retry-after"]) <= PUBLIC_WINDOW
    assert json.loads(body)["errors"][0]["rule"] == "rate_limit"
    status, headers, page = get(served, "/verify/TRK-2026-000001-A", "203.0.113.9", accept="text/html")
    assert status == 429
    assert headers["content-type"].startswith("text/html")
    assert "Please wait a moment" in page
    assert f"Wait {headers['retry-after']} seconds" in page

    assert get(served, numbers[0], "203.0.113.10")[0] != 429, "another address is not limited"
    assert get(served, "/healthz", "203.0.113.9")[0] == 200, "other doors are not counted"
