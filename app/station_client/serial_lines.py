"""Lines from a file or a serial device (a pty works too): a file is read to its end, a device until
it has been silent for `idle_timeout` seconds."""

from __future__ import annotations

import os
import select
import termios
import tty
from collections.abc import Callable, Iterator
from pathlib import Path

from app.station_client.files import SourceError


def _configure(fd: int, baud: int) -> None:
    """Raw 8N1 at `baud` bit/s, so the indicator's bytes arrive as sent."""
    speed = getattr(termios, f"B{baud}", None)
    if speed is None:
        raise SourceError(f"{baud} is not a serial speed this system knows (try 9600)")
    tty.setraw(fd)
    attributes = termios.tcgetattr(fd)
    attributes[4] = attributes[5] = speed
    termios.tcsetattr(fd, termios.TCSANOW, attributes)


def _device_lines(fd: int, idle_timeout: float) -> Iterator[str]:
    pending = b""
    while True:
        ready, _, _ = select.select([fd], [], [], idle_timeout)
        if not ready:
            break
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # the other end of a pty closed
            break
        if not chunk:
            break
        pending += chunk.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
        *complete, pending = pending.split(b"\n")
        for line in complete:
            yield line.decode("ascii", errors="replace")
    if pending:
        yield pending.decode("ascii", errors="replace")


def read_lines(
    path: Path, *, baud: int = 9600, idle_timeout: float = 30.0, ready: Callable[[], None] | None = None
) -> Iterator[str]:
    """Every line from `path`: a regular file to its end, a serial device or pty until it falls silent;
    `ready` is called once the device is open and configured (what arrived before is discarded)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOCTTY)
    except OSError as error:
        raise SourceError(f"{path}: cannot open ({error.strerror})") from error
    try:
        if os.isatty(fd):
            _configure(fd, baud)
            if ready is not None:
                ready()
            yield from _device_lines(fd, idle_timeout)
        else:
            with os.fdopen(os.dup(fd), encoding="ascii", errors="replace") as handle:
                for line in handle:
                    yield line.rstrip("\r\n")
    finally:
        os.close(fd)
