"""A small table for the person at the terminal (fit report, recorded limits, LeRobot comparison),
built by the core and drawn by the command line, which alone knows about colours and rich.

Numpy-free: the command modules import it for its types."""

from __future__ import annotations

from dataclasses import dataclass, field

# plain text, or (text, style) segments where a style is a colour such as "yellow" ("" for none)
Cell = str | tuple[tuple[str, str], ...]


@dataclass(frozen=True)
class Summary:
    title: str
    columns: tuple[str, ...]
    rows: list[tuple[Cell, ...]] = field(default_factory=list)
    left: tuple[str, ...] = ()  # columns aligned left; the others are numbers, aligned right
    no_wrap: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)  # lines printed after the table
