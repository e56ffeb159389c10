"""SARIF that GitHub's code scanning accepts: valid against the OASIS 2.1.0 schema (formats
checked), URIs percent-encoded and relative to the repository root with a uriBaseId whatever way
the input was named, a region with its end, and fingerprints that follow the text, not the line."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.lint.finding import Finding, Severity
from armtool.output.base import LintReport
from armtool.output.sarif import MAX_DESCRIPTION, SarifFormatter, lint_tool

REPO = Path(__file__).resolve().parents[2]
SCHEMA = REPO / "fixtures" / "sarif" / "sarif-schema-2.1.0.json"
BROKEN = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="upper">
    <inertial>
      <mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/>
    <child link="upper"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="0"/>
  </joint>
</robot>
"""  # one finding: U203 on velocity="0"


def validate(doc: dict[str, Any]) -> None:
    """`doc` against the OASIS SARIF 2.1.0 schema, with `format` enforced (uri, uri-reference)."""
    import jsonschema

    schema = json.loads(SCHEMA.read_text())
    validator = jsonschema.Draft4Validator(schema, format_checker=jsonschema.FormatChecker())
    errors = sorted(validator.iter_errors(doc), key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{list(e.path)}: {e.message}" for e in errors[:5])


def lint_sarif(*args: str, cwd: Path) -> dict[str, Any]:
    old = Path.cwd()
    os.chdir(cwd)
    try:
        result = CliRunner().invoke(app, ["lint", "--format", "sarif", *args])
    finally:
        os.chdir(old)
    assert result.exit_code == 1, result.output
    doc: dict[str, Any] = json.loads(result.stdout)
    return doc


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    """A checkout whose package folder has a space, an umlaut and a hash in its name."""
    (tmp_path / "ws" / ".git").mkdir(parents=True)
    package = tmp_path / "ws" / "src" / "arm ü#1" / "urdf"
    package.mkdir(parents=True)
    (package / "arm.urdf").write_text(BROKEN)
    return tmp_path / "ws"


def test_the_schema_check_catches_what_code_scanning_rejects() -> None:
    import jsonschema

    doc = json.loads(SarifFormatter(root=REPO).render(LintReport([], 1), color=False))
    validate(doc)
    doc["runs"][0]["results"] = [
        {
            "message": {"text": "x"},
            "locations": [{"physicalLocation": {"artifactLocation": {"uri": "src/arm ü#1/arm.urdf"}}}],
        }
    ]
    with pytest.raises(AssertionError, match="uri-reference"):
        validate(doc)
    assert jsonschema.FormatChecker().conforms("src/arm%20%C3%BC%231/arm.urdf", "uri-reference")


@pytest.mark.parametrize("how", ["relative", "absolute", "from a subdirectory"])
def test_uris_are_encoded_and_relative_to_the_repository_root(repo: Path, how: str) -> None:
    urdf = repo / "src" / "arm ü#1" / "urdf" / "arm.urdf"
    if how == "relative":
        doc = lint_sarif("src/arm ü#1/urdf/arm.urdf", cwd=repo)
    elif how == "absolute":
        doc = lint_sarif(str(urdf), cwd=repo)
    else:
        doc = lint_sarif(str(urdf), cwd=repo / "src")
    validate(doc)
    run = doc["runs"][0]
    (result,) = run["results"]
    location = result["locations"][0]["physicalLocation"]
    assert location["artifactLocation"] == {"uri": "src/arm%20%C3%BC%231/urdf/arm.urdf", "uriBaseId": "%SRCROOT%"}
    assert run["originalUriBaseIds"]["%SRCROOT%"]["uri"] == Path(os.path.realpath(repo)).as_uri() + "/"


def test_a_file_outside_the_repository_gets_an_absolute_file_uri(repo: Path, tmp_path: Path) -> None:
    outside = tmp_path / "elsewhere" / "a b.urdf"
    outside.parent.mkdir()
    outside.write_text(BROKEN)
    doc = lint_sarif(str(outside), cwd=repo)
    validate(doc)
    uri = doc["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]
    assert uri == {"uri": Path(os.path.realpath(outside)).as_uri()} and "%20" in uri["uri"]


def test_regions_have_their_end_and_fingerprints_follow_the_text(repo: Path) -> None:
    urdf = repo / "src" / "arm ü#1" / "urdf" / "arm.urdf"
    first = lint_sarif(str(urdf), cwd=repo)["runs"][0]["results"][0]
    region = first["locations"][0]["physicalLocation"]["region"]
    line = BROKEN.splitlines()[region["startLine"] - 1]
    token = line[region["startColumn"] - 1 : region["endColumn"] - 1]
    assert region["endLine"] == region["startLine"] and token == 'velocity="0"'  # U203 points at the attribute
    fingerprint = first["partialFingerprints"]["primaryLocationLineHash"]
    assert fingerprint.endswith(":1") and len(fingerprint.split(":")[0]) == 16
    # Lines added above move the finding, not its fingerprint.
    urdf.write_text(BROKEN.replace("<robot", "<!-- a comment -->\n\n<robot", 1))
    moved = lint_sarif(str(urdf), cwd=repo)["runs"][0]["results"][0]
    assert moved["locations"][0]["physicalLocation"]["region"]["startLine"] == region["startLine"] + 2
    assert moved["partialFingerprints"]["primaryLocationLineHash"] == fingerprint


def test_an_element_region_spans_its_start_tag_and_equal_text_gets_its_own_count(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    joint = '  <joint name="a"\n         type="x">\n  </joint>\n'
    tail = "  <!--" + " padding" * 20 + " -->\n"  # the same 100 characters follow both joints
    path.write_text('<robot name="r">\n' + joint + tail + joint + tail + "</robot>\n")
    findings = [
        Finding(str(path), 2, 3, "U105", "unknown-joint-type", Severity.ERROR, "joint 'a': type 'x'"),
        Finding(str(path), 6, 3, "U105", "unknown-joint-type", Severity.ERROR, "joint 'a': type 'x'"),
    ]
    doc = json.loads(SarifFormatter(root=tmp_path).render(LintReport(findings, 1), color=False))
    validate(doc)
    results = doc["runs"][0]["results"]
    regions = [r["locations"][0]["physicalLocation"]["region"] for r in results]
    assert regions[0] == {"startLine": 2, "startColumn": 3, "endLine": 3, "endColumn": 19}  # through `type="x">`
    hashes = [r["partialFingerprints"]["primaryLocationLineHash"] for r in results]
    assert hashes[0].split(":")[0] == hashes[1].split(":")[0] and [h[-2:] for h in hashes] == [":1", ":2"]


def test_every_rule_description_fits_githubs_limit() -> None:
    doc = json.loads(SarifFormatter(root=REPO).render(LintReport([], 1), color=False))
    rules = doc["runs"][0]["tool"]["driver"]["rules"]
    assert len(rules) == len(lint_tool().rules)
    for rule in rules:
        assert 0 < len(rule["fullDescription"]["text"]) <= MAX_DESCRIPTION
        assert 0 < len(rule["shortDescription"]["text"]) <= MAX_DESCRIPTION
        assert "Why is this bad?" in rule["help"]["text"]
    long = next(r for r in lint_tool().rules if len(r.documentation) > MAX_DESCRIPTION)  # S109's is
    shown = next(r for r in rules if r["id"] == long.code)
    assert shown["fullDescription"]["text"].endswith("…") and shown["help"]["text"] == long.documentation


def test_traj_check_sarif_is_valid_too(tmp_path: Path) -> None:
    from armtool.traj.check import sarif_tool

    path = tmp_path / "t r.csv"
    path.write_text("time_s,j1_rad\n0,0\n0.01,5\n")
    finding = Finding(str(path), 3, 1, "T301", "velocity-over-limit", Severity.ERROR, "too fast")
    doc = json.loads(SarifFormatter(sarif_tool(), root=tmp_path).render(LintReport([finding], 1), color=False))
    validate(doc)
    location = doc["runs"][0]["results"][0]["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"] == "t%20r.csv"
    assert location["region"] == {"startLine": 3, "startColumn": 1, "endLine": 3, "endColumn": 7}
