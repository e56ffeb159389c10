"""CSV rows with the file line each starts on; the csv module's own errors become input errors.

Python's csv module refuses a field over 128 KiB ("field larger than field limit") and a NUL
byte with `csv.Error`, which no reader of trajectories or servo measurements expects: it reached
the user as "internal error". Every such reader takes its rows from here instead.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence

from armtool.errors import ArmtoolError


def csv_rows(
    lines: Sequence[str], source: str, first_line: int = 1, what: str = "CSV file"
) -> list[tuple[int, list[str]]]:
    """Each row of `lines` (consecutive lines of `source`, the first of them line `first_line`),
    with the line it starts on. A row the csv module cannot read is an ArmtoolError at file:line."""
    reader = csv.reader(io.StringIO("\n".join(lines)))
    rows: list[tuple[int, list[str]]] = []
    while True:
        start = reader.line_num + 1
        try:
            row = next(reader)
        except StopIteration:
            return rows
        except csv.Error as exc:
            line = first_line + max(reader.line_num, start) - 1
            text = str(exc)
            if "field larger than field limit" in text:
                problem = f"a field longer than {csv.field_size_limit()} characters"
                hint = f"a {what} holds short values, one row per line: is this the right file?"
            else:
                problem = text
                hint = "save it as plain comma-separated text"
            raise ArmtoolError(f"{what} cannot be read as CSV: {problem}", f"{source}:{line}", hint) from None
        rows.append((first_line + start - 1, row))
