"""Where an element of an expanded (xacro) document was written."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class SourceLine:
    path: Path
    line: int


@dataclass(frozen=True)
class Origin:
    """Where an expanded element was written, and the macro calls (outermost first) that produced it."""

    source: SourceLine | None
    calls: tuple[SourceLine, ...] = ()
