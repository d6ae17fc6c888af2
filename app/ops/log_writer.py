"""The process's log writer: records are queued by whoever logs and written by one thread, in batches.

The thread wakes every `INTERVAL` seconds and writes all that was queued meanwhile in one write. A
thread blocked on the queue instead woke at every line: under a flood of public verifications each
request then paid a thread switch for its access line, about a third of what a kept answer costs
(bench/RESULTS.md). A line is written at most `INTERVAL` late; `flush()` writes at once.
"""

from __future__ import annotations

import logging
import queue
import sys
import threading
import traceback
from collections.abc import Callable
from typing import TextIO

INTERVAL = 0.05


def standard_error() -> TextIO:
    """The standard error of the moment: the thread outlives whoever set it up, and a stream held from
    then may since have been replaced and closed (pytest's capture of one test, say)."""
    return sys.stderr


class BatchWriter:
    """One thread that formats the queued records and writes them to a stream, a batch at a time."""

    def __init__(
        self,
        formatter: logging.Formatter,
        stream: Callable[[], TextIO] = standard_error,
        interval: float = INTERVAL,
    ) -> None:
        self.queue: queue.SimpleQueue[logging.LogRecord] = queue.SimpleQueue()
        self.formatter = formatter
        self.stream = stream
        self.interval = interval
        self._draining = threading.Lock()  # a flush and the thread never interleave their batches
        self._stopped = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        """Start the writing thread (a daemon: `stop` at exit writes what is left)."""
        self._stopped.clear()
        self._thread = threading.Thread(target=self._run, name="trikecert-log-writer", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Write what is queued and stop the thread."""
        self._stopped.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None
        self.flush()

    def flush(self) -> None:
        """Write every record queued so far, now."""
        with self._draining:
            records: list[logging.LogRecord] = []
            while True:
                try:
                    records.append(self.queue.get_nowait())
                except queue.Empty:
                    break
            if records:
                self._write(records)

    def _write(self, records: list[logging.LogRecord]) -> None:
        lines = []
        for record in records:
            try:
                lines.append(self.formatter.format(record) + "\n")
            except Exception:  # left out with a trace, as logging.Handler.handleError does
                traceback.print_exc(file=self.stream())
        stream = self.stream()
        stream.write("".join(lines))
        stream.flush()

    def _run(self) -> None:
        while not self._stopped.wait(self.interval):
            self.flush()
