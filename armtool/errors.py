"""One error type for everything the user can fix: what went wrong, where, how to fix it."""

from __future__ import annotations

from enum import IntEnum


class ExitCode(IntEnum):
    """Exit codes shared by every subcommand (as ruff: 0 clean, 1 findings, 2 error)."""

    OK = 0
    FINDINGS = 1
    ERROR = 2


class ArmtoolError(Exception):
    """A problem the user can act on. Core code raises it; only `armtool.cli` prints it."""

    def __init__(self, what: str, where: str | None = None, hint: str | None = None) -> None:
        super().__init__(what)
        self.what = what
        self.where = where
        self.hint = hint

    def __reduce__(self) -> tuple[type[ArmtoolError], tuple[str, str | None, str | None]]:
        # Keep where/hint when the error crosses a process boundary (parallel lint workers).
        return (type(self), (self.what, self.where, self.hint))

    def __str__(self) -> str:
        text = self.what if self.where is None else f"{self.what} ({self.where})"
        return text if self.hint is None else f"{text}\n  hint: {self.hint}"
