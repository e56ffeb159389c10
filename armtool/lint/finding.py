"""What a rule reports: a frozen Finding at a file:line:col, with an optional safe text edit."""

from __future__ import annotations

from dataclasses import dataclass, replace
from enum import Enum
from pathlib import Path


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


@dataclass(frozen=True)
class Edit:
    """Replace source[start:end] of `path` with `replacement` (offsets in characters)."""

    path: Path
    start: int
    end: int
    replacement: str


@dataclass(frozen=True)
class Finding:
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
        return replace(self, severity=severity)

    @property
    def sort_key(self) -> tuple[str, int, int, str]:
        return (self.path, self.line, self.column, self.code)
