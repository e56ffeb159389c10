"""A core-built summary (armtool.servo.summary.Summary: the tables `limits` and `servo-lut` print) drawn
by rich on stderr."""

from __future__ import annotations

from typing import TYPE_CHECKING

from armtool.console import stderr

if TYPE_CHECKING:  # rich's tables load only when a summary is printed
    from rich.table import Table

    from armtool.servo.summary import Summary


def summary_table(summary: Summary) -> Table:
    """A core-built table as rich draws it."""
    from rich.table import Table
    from rich.text import Text

    table = Table(title=Text(summary.title), title_justify="left")
    for col in summary.columns:
        table.add_column(col, justify="left" if col in summary.left else "right", no_wrap=col in summary.no_wrap)
    for row in summary.rows:
        table.add_row(*(Text(cell) if isinstance(cell, str) else Text.assemble(*cell) for cell in row))
    return table


def print_summary(summary: Summary) -> None:
    """A core-built table, and its notes, on stderr."""
    stderr().print(summary_table(summary))
    from armtool.console import say

    for note in summary.notes:
        say(note)
