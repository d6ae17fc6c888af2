"""The log writer: every queued line is written once and in order, a batch per write; a flush writes at
once, and stopping writes what is left."""

from __future__ import annotations

import io
import logging
import threading

from app.ops.log_writer import BatchWriter


class CountedStream(io.StringIO):
    """A stream that counts its writes."""

    def __init__(self) -> None:
        super().__init__()
        self.writes = 0
        self.lock = threading.Lock()

    def write(self, text: str) -> int:
        with self.lock:
            self.writes += 1
            return super().write(text)


def record(number: int) -> logging.LogRecord:
    return logging.LogRecord("trikecert.access", logging.INFO, __file__, 0, f"line {number}", (), None)


def test_a_burst_is_written_in_order_in_few_writes_and_a_flush_writes_at_once() -> None:
    stream = CountedStream()
    writer = BatchWriter(logging.Formatter("%(message)s"), stream=lambda: stream, interval=3600)
    writer.start()
    try:
        for number in range(1000):
            writer.queue.put(record(number))
        assert stream.getvalue() == ""  # the thread waits its interval: nothing is written yet
        writer.flush()
        assert stream.getvalue() == "".join(f"line {number}\n" for number in range(1000))
        assert stream.writes == 1
    finally:
        writer.stop()


def test_stopping_writes_what_is_left_and_the_thread_writes_by_itself() -> None:
    stream = CountedStream()
    writer = BatchWriter(logging.Formatter("%(message)s"), stream=lambda: stream, interval=0.01)
    writer.start()
    writer.queue.put(record(1))
    for _ in range(500):  # the thread's own write, within a few intervals
        if stream.getvalue():
            break
        threading.Event().wait(0.01)
    assert stream.getvalue() == "line 1\n"
    writer.queue.put(record(2))
    writer.stop()
    assert stream.getvalue() == "line 1\nline 2\n"


def test_a_record_that_cannot_be_formatted_leaves_the_others_written() -> None:
    stream = CountedStream()
    writer = BatchWriter(logging.Formatter("%(message)s"), stream=lambda: stream, interval=3600)
    broken = logging.LogRecord("trikecert", logging.INFO, __file__, 0, "%d", ("not a number",), None)
    for item in (record(1), broken, record(2)):
        writer.queue.put(item)
    writer.flush()
    assert stream.getvalue().startswith("Traceback")
    assert stream.getvalue().endswith("line 1\nline 2\n")
