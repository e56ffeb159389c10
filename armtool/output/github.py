"""GitHub Actions workflow commands: findings appear as annotations on the pull request."""

from __future__ import annotations

from armtool.lint.finding import Severity
from armtool.output.base import LintReport

_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def _escape(text: str, *, prop: bool = False) -> str:
    text = text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        text = text.replace(":", "%3A").replace(",", "%2C")
    return text


class GithubFormatter:
    def render(self, report: LintReport, *, color: bool) -> str:
        lines = []
        for f in report.findings:
            message = f.message + (f" (hint: {f.hint})" if f.hint else "")
            lines.append(
                f"::{_COMMAND[f.severity]} file={_escape(f.path, prop=True)},line={f.line},col={f.column},"
                f"title={_escape(f'{f.code} {f.name}', prop=True)}::{_escape(message)}"
            )
        return "\n".join(lines) + ("\n" if lines else "")
