"""SARIF 2.1.0 for code-scanning UIs; each rule's documentation comes from its docstring.
The lint rules are the default; `traj check` passes its own codes and driver name."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass

from armtool import __version__
from armtool.lint.finding import Severity
from armtool.lint.registry import RULES
from armtool.output.base import LintReport

_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
HELP_URI = "https://github.com/armtool/armtool/blob/main/docs/rules.md#{code}"


@dataclass(frozen=True)
class SarifRule:
    """One `reportingDescriptor`: what a code means and where its documentation lives."""

    code: str
    name: str
    summary: str
    documentation: str
    severity: Severity
    help_uri: str


@dataclass(frozen=True)
class SarifTool:
    """The `tool.driver` of the run: its name and every rule it can report."""

    name: str
    rules: Sequence[SarifRule]


def lint_tool() -> SarifTool:
    """`armtool lint`'s driver: every registered rule, documented by its docstring."""
    return SarifTool(
        "armtool",
        [
            SarifRule(
                rule.code,
                rule.name,
                rule.summary(),
                rule.documentation(),
                rule.severity,
                HELP_URI.format(code=rule.code.lower()),
            )
            for rule in RULES
        ],
    )


class SarifFormatter:
    def __init__(self, tool: SarifTool | None = None) -> None:
        self._tool = tool

    def render(self, report: LintReport, *, color: bool) -> str:
        tool = self._tool or lint_tool()
        rules = [
            {
                "id": rule.code,
                "name": rule.name,
                "shortDescription": {"text": rule.summary},
                "fullDescription": {"text": rule.documentation},
                "help": {"text": rule.documentation},
                "helpUri": rule.help_uri,
                "defaultConfiguration": {"level": _LEVEL[rule.severity]},
            }
            for rule in tool.rules
        ]
        index = {rule.code: i for i, rule in enumerate(tool.rules)}
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
                            "name": tool.name,
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
