"""What a rule reports: an immutable Finding at a file:line:col, with an optional safe text edit.

NamedTuples, not dataclasses: a frozen dataclass costs ~1 ms to create at import, and
`armtool lint` start-up is paid in every pre-commit run.
"""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import NamedTuple


class Severity(str, Enum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"info": 0, "warning": 1, "error": 2}[self.value]


class FixSafety(str, Enum):
    """Whether `--fix` may apply a rule's edit without asking (ruff's fix safety)."""

    SAFE = "safe"
    NONE = "none"


class Edit(NamedTuple):
    """Replace source[start:end] of `path` with `replacement` (offsets in characters)."""

    path: Path
    start: int
    end: int
    replacement: str


class Finding(NamedTuple):
    path: str
    line: int
    column: int
    code: str
    name: str
    severity: Severity
    message: str
    hint: str | None = None
    edit: Edit | None = None
    # Other source lines this finding stands for (macro definition, call sites): ignore comments there count too.
    related: tuple[tuple[str, int], ...] = ()

    def with_severity(self, severity: Severity) -> Finding:
        return self._replace(severity=severity)

    @property
    def sort_key(self) -> tuple[str, int, int, str]:
        return (self.path, self.line, self.column, self.code)
