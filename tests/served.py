"""What every test of a served process needs: a free port to serve on, and a wait until the process
answers there (or a failure that says why it never did)."""

from __future__ import annotations

import socket
import subprocess
import time
import urllib.request
from pathlib import Path
from typing import Any


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nobody listens on."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port


def wait_until_ready(
    url: str,
    process: subprocess.Popen[Any] | None = None,
    *,
    timeout: float = 60.0,
    in_a_row: int = 1,
    log: Path | None = None,
) -> str:
    """Wait until `url` answers 200 `in_a_row` times in a row (several: past the start of every worker,
    not only the first); return the last answer's body. Fails, with the server's log when there is
    one (or its piped output), if the process exits or `timeout` seconds pass first."""
    deadline = time.monotonic() + timeout
    answered = 0
    while True:
        try:
            with urllib.request.urlopen(url, timeout=2) as response:
                body: str = response.read().decode()
                answered += 1
        except OSError:  # refused, reset, timed out, or an HTTP error such as 503 while starting
            answered = 0
        if answered >= in_a_row:
            return body
        exited = process is not None and process.poll() is not None
        if exited or time.monotonic() > deadline:
            said = ""
            if log is not None and log.is_file():
                said = f":\n{log.read_text()}"
            elif exited and process is not None and process.stdout is not None:
                output = process.stdout.read()
                said = f":\n{output.decode() if isinstance(output, bytes) else output}"
            happened = "exited" if exited else f"did not answer within {timeout:g} s"
            raise AssertionError(f"the served process {happened} ({url}){said}")
        time.sleep(0.05 if answered else 0.1)
