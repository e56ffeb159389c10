"""A formatter turns a lint report into the text written to stdout."""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple, Protocol

from armtool.lint.finding import Finding, Severity

if TYPE_CHECKING:
    from armtool.lint.checked import PackageChecked


class LintReport(NamedTuple):
    findings: list[Finding]
    files_checked: int
    fixable: int = 0
    checked: list[PackageChecked] = []  # noqa: RUF012 (read-only): per package, what was checked against what

    def count(self, severity: Severity) -> int:
        return sum(1 for f in self.findings if f.severity is severity)


class Formatter(Protocol):
    def render(self, report: LintReport, *, color: bool) -> str: ...
