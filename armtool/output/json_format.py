"""Machine output: one JSON document with `schema_version` and a list of findings."""

from __future__ import annotations

import json

from armtool.lint.finding import Severity
from armtool.output.base import LintReport

SCHEMA_VERSION = 1


class JsonFormatter:
    def render(self, report: LintReport, *, color: bool) -> str:
        doc = {
            "schema_version": SCHEMA_VERSION,
            "files_checked": report.files_checked,
            "summary": {sev.value: report.count(sev) for sev in (Severity.ERROR, Severity.WARNING, Severity.INFO)},
            "checked": [p.as_dict() for p in report.checked],
            "findings": [
                {
                    "path": f.path,
                    "line": f.line,
                    "column": f.column,
                    "code": f.code,
                    "name": f.name,
                    "severity": f.severity.value,
                    "message": f.message,
                    "fix": f.hint,
                    "fixable": f.edit is not None,
                }
                for f in report.findings
            ],
        }
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
