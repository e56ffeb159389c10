"""A formatter turns a lint report into the text written to stdout."""

from __future__ import annotations

from typing import NamedTuple, Protocol

from armtool.lint.finding import Finding, Severity


class LintReport(NamedTuple):
    findings: list[Finding]
    files_checked: int
    fixable: int = 0

    def count(self, severity: Severity) -> int:
        return sum(1 for f in self.findings if f.severity is severity)


class Formatter(Protocol):
    def render(self, report: LintReport, *, color: bool) -> str: ...
