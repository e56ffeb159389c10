"""SARIF 2.1.0 for code-scanning UIs; each rule's documentation comes from its docstring."""

from __future__ import annotations

import json

from armtool import __version__
from armtool.lint.finding import Severity
from armtool.lint.registry import RULES
from armtool.output.base import LintReport

_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
HELP_URI = "https://github.com/armtool/armtool/blob/main/docs/rules.md#{code}"


class SarifFormatter:
    def render(self, report: LintReport, *, color: bool) -> str:
        rules = [
            {
                "id": rule.code,
                "name": rule.name,
                "shortDescription": {"text": rule.summary()},
                "fullDescription": {"text": rule.documentation()},
                "help": {"text": rule.documentation()},
                "helpUri": HELP_URI.format(code=rule.code.lower()),
                "defaultConfiguration": {"level": _LEVEL[rule.severity]},
            }
            for rule in RULES
        ]
        index = {rule.code: i for i, rule in enumerate(RULES)}
        results = []
        for f in report.findings:
            text = f.message + (f"\nhint: {f.hint}" if f.hint else "")
            results.append(
                {
                    "ruleId": f.code,
                    "ruleIndex": index.get(f.code, 0),
                    "level": _LEVEL[f.severity],
                    "message": {"text": text},
                    "locations": [
                        {
                            "physicalLocation": {
                                "artifactLocation": {"uri": f.path.replace("\\", "/")},
                                "region": {"startLine": f.line, "startColumn": f.column},
                            }
                        }
                    ],
                }
            )
        doc = {
            "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
            "version": "2.1.0",
            "runs": [
                {
                    "tool": {
                        "driver": {
                            "name": "armtool",
                            "version": __version__,
                            "informationUri": "https://github.com/armtool/armtool",
                            "rules": rules,
                        }
                    },
                    "results": results,
                }
            ],
        }
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
