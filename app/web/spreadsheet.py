"""CSV downloads: cells a spreadsheet will not run as formulas, written out as the rows come."""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable, Iterator

from starlette.responses import StreamingResponse

# A spreadsheet runs a cell starting with one of these as a formula (OWASP's "CSV injection").
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")

Cell = str | int | None
CHUNK_ROWS = 500


def safe_cell(value: Cell) -> Cell:
    """A text cell a spreadsheet shows as typed: one starting like a formula gets a leading apostrophe."""
    if isinstance(value, str) and value.startswith(FORMULA_STARTS):
        return "'" + value
    return value


def csv_lines(header: Iterable[str], rows: Iterable[Iterable[Cell]]) -> Iterator[str]:
    """The header and the rows as CSV (CRLF lines, as RFC 4180 has it), every cell made safe, a few
    hundred rows at a time."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\r\n")
    writer.writerow(header)
    for count, cells in enumerate(rows, start=1):
        writer.writerow([safe_cell(cell) for cell in cells])
        if count % CHUNK_ROWS == 0:
            yield buffer.getvalue()
            buffer.seek(0)
            buffer.truncate()
    yield buffer.getvalue()


def csv_download(header: Iterable[str], rows: Iterable[Iterable[Cell]], filename: str) -> StreamingResponse:
    """The rows as a CSV file to save, sent as they are read rather than built in memory first."""
    return StreamingResponse(
        csv_lines(header, rows),
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": f'attachment; filename="{filename}"'},
    )
