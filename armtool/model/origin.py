"""Where an element of an expanded (xacro) document was written."""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple


class SourceLine(NamedTuple):
    path: Path
    line: int


class Origin(NamedTuple):
    """Where an expanded element was written, and the macro calls (outermost first) that produced it."""

    source: SourceLine | None
    calls: tuple[SourceLine, ...] = ()
