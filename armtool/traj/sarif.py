"""SARIF 2.1.0 for `traj check` findings, with the trajectory codes as rules."""

from __future__ import annotations

import json

from armtool import __version__
from armtool.lint.finding import Finding, Severity
from armtool.traj.check import CODES

_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def render_sarif(findings: list[Finding]) -> str:
    codes = list(CODES.values())
    rules = [{"id": c.code, "name": c.name, "shortDescription": {"text": c.summary},
              "defaultConfiguration": {"level": _LEVEL[c.severity]}} for c in codes]
    index = {c.code: i for i, c in enumerate(codes)}
    results = [{
        "ruleId": f.code, "ruleIndex": index[f.code], "level": _LEVEL[f.severity],
        "message": {"text": f.message + (f"\nhint: {f.hint}" if f.hint else "")},
        "locations": [{"physicalLocation": {"artifactLocation": {"uri": f.path.replace("\\", "/")},
                                            "region": {"startLine": f.line, "startColumn": f.column}}}],
    } for f in findings]
    doc = {"$schema": "https://json.schemastore.org/sarif-2.1.0.json", "version": "2.1.0",
           "runs": [{"tool": {"driver": {"name": "armtool traj check", "version": __version__,
                                         "informationUri": "https://github.com/armtool/armtool", "rules": rules}},
                     "results": results}]}
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
