"""text, sarif and github renderings of the same findings."""

from __future__ import annotations

import json

from armtool.lint.finding import Finding, Severity
from armtool.lint.registry import RULES
from armtool.output.base import LintReport
from armtool.output.registry import FORMATS, OutputFormat, formatter

FINDINGS = [
    Finding(
        "a/r.urdf", 3, 5, "U101", "unknown-link", Severity.ERROR, "joint 'j': child link 'b' does not exist", "add it"
    ),
    Finding(
        "a/r.urdf", 7, 1, "U402", "root-inertia", Severity.INFO, "root link 'a' has an <inertial>, which KDL ignores"
    ),
]
REPORT = LintReport(FINDINGS, files_checked=2)


def test_every_format_is_registered() -> None:
    assert set(FORMATS) == set(OutputFormat)


def test_text_groups_by_file_and_summarises() -> None:
    text = formatter(OutputFormat.TEXT).render(REPORT, color=False)
    lines = text.splitlines()
    assert lines[0] == "a/r.urdf"
    assert lines[1].startswith("  3:5  error    U101 unknown-link  joint 'j'")
    assert lines[-1] == "Found 2 problems (1 error, 1 info) in 2 files."
    assert "\x1b[" not in text and "\x1b[" in formatter(OutputFormat.TEXT).render(REPORT, color=True)


def test_text_when_clean() -> None:
    assert "All checks passed (1 file checked)." in formatter(OutputFormat.TEXT).render(LintReport([], 1), color=False)


def test_sarif_carries_rule_docs_and_locations() -> None:
    doc = json.loads(formatter(OutputFormat.SARIF).render(REPORT, color=False))
    assert doc["version"] == "2.1.0"
    run = doc["runs"][0]
    rules = run["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules] == [r.code for r in RULES]
    assert all("Why is this bad?" in r["fullDescription"]["text"] and r["helpUri"] for r in rules)
    first = run["results"][0]
    assert first["ruleId"] == "U101" and first["level"] == "error"
    # a/r.urdf does not exist: the region is the one character the finding points at
    assert first["locations"][0]["physicalLocation"]["region"] == {
        "startLine": 3,
        "startColumn": 5,
        "endLine": 3,
        "endColumn": 6,
    }
    assert run["results"][1]["level"] == "note"
    assert rules[first["ruleIndex"]]["id"] == "U101"


def test_github_annotations_escape_properties() -> None:
    out = formatter(OutputFormat.GITHUB).render(REPORT, color=False).splitlines()
    assert (
        out[0]
        == "::error file=a/r.urdf,line=3,col=5,title=U101 unknown-link::joint 'j': child link 'b' does not exist (hint: add it)"
    )
    assert out[1].startswith("::notice ")


def test_sarif_takes_another_tool_and_its_rules() -> None:
    from armtool.output.sarif import SarifFormatter, SarifRule, SarifTool

    tool = SarifTool("other", [SarifRule("U101", "x", "short", "long", Severity.WARNING, "https://example.org/u101")])
    driver = json.loads(SarifFormatter(tool).render(REPORT, color=False))["runs"][0]["tool"]["driver"]
    assert driver["name"] == "other"
    assert driver["rules"] == [
        {
            "id": "U101",
            "name": "x",
            "shortDescription": {"text": "short"},
            "fullDescription": {"text": "long"},
            "help": {"text": "long"},
            "helpUri": "https://example.org/u101",
            "defaultConfiguration": {"level": "warning"},
        }
    ]
