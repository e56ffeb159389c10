"""Human output: findings grouped by file, coloured on a terminal, one summary line.

Plain ANSI codes instead of rich: importing and rendering with rich costs `armtool lint`
about 40 ms, which every pre-commit run would pay.
"""

from __future__ import annotations

from itertools import groupby

from armtool.lint.finding import Severity
from armtool.output.base import LintReport

_SEVERITY_STYLE = {Severity.ERROR: "1;31", Severity.WARNING: "33", Severity.INFO: "36"}


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


class TextFormatter:
    def render(self, report: LintReport, *, color: bool) -> str:
        def paint(text: str, style: str) -> str:
            return f"\x1b[{style}m{text}\x1b[0m" if color else text

        out: list[str] = []
        for path, items in groupby(report.findings, key=lambda f: f.path):
            out.append(paint(path, "1"))
            for f in items:
                fixable = " " + paint("[*]", "32") if f.edit is not None else ""
                out.append(
                    f"  {f.line}:{f.column}  {paint(f'{f.severity.value:<7}', _SEVERITY_STYLE[f.severity])}  "
                    f"{paint(f.code, '1')} {paint(f.name, '2')}  {f.message}{fixable}"
                )
                if f.hint:
                    out.append(f"      {paint('hint:', '2')} {f.hint}")
            out.append("")
        files = _plural(report.files_checked, "file")
        if report.checked:
            from armtool.lint.checked import lines

            out += [paint(line, "2") for line in lines(report.checked)]
        unpaired = sum(len(p.unpaired) for p in report.checked)
        if not report.findings and unpaired:
            out.append(
                f"No problems in what was checked ({files}); {_plural(unpaired, 'file')} could not be paired "
                "with the file its checks need (see checked:)."
            )
        elif not report.findings:
            out.append(f"{paint('All checks passed', '32')} ({files} checked).")
        else:
            counts = ", ".join(
                _plural(report.count(s), s.value)
                for s in (Severity.ERROR, Severity.WARNING, Severity.INFO)
                if report.count(s)
            )
            line = f"Found {_plural(len(report.findings), 'problem')} ({counts}) in {files}."
            if report.fixable:
                line += f" {report.fixable} fixable with --fix {paint('[*]', '32')}."
            out.append(line)
        return "\n".join(out) + "\n"
