"""The `armtool` command: help, version, one error path with exit code 2 and no traceback."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from armtool import __version__
from armtool.cli import app
from armtool.lint.registry import RULES


def run(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "armtool", *args],
        capture_output=True,
        text=True,
        env={**os.environ, **(env or {})},
        timeout=120,
    )


def test_help_lists_every_command() -> None:
    result = CliRunner().invoke(app, ["--help"])
    assert result.exit_code == 0
    for command in ("lint", "lint-urdf", "rules"):
        assert command in result.stdout


def test_version() -> None:
    result = CliRunner().invoke(app, ["--version"])
    assert result.exit_code == 0 and result.stdout.strip() == f"armtool {__version__}"


def test_rules_list_and_one_rule() -> None:
    listing = CliRunner().invoke(app, ["rules"])
    assert listing.exit_code == 0
    assert len(listing.stdout.strip().splitlines()) == len(RULES)
    one = CliRunner().invoke(app, ["rules", "rpy-out-of-range"])
    assert one.exit_code == 0 and "U301" in one.stdout and "Why is this bad?" in one.stdout


def test_unknown_rule_is_exit_2_with_suggestion() -> None:
    result = run("rules", "U30")
    assert result.returncode == 2
    assert "error: no rule 'U30'" in result.stderr and "Traceback" not in result.stderr


def test_missing_path_is_exit_2_without_traceback(tmp_path: Path) -> None:
    result = run("lint", str(tmp_path / "nope.urdf"))
    assert result.returncode == 2
    assert "no such file or directory" in result.stderr and "nope.urdf" in result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""


def test_debug_env_shows_traceback(tmp_path: Path) -> None:
    result = run("lint", str(tmp_path / "nope.urdf"), env={"ARMTOOL_DEBUG": "1"})
    assert result.returncode != 0 and "Traceback" in result.stderr


def test_bad_xacro_arg_is_usage_error(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text('<robot name="r"><link name="a"/></robot>')
    result = CliRunner().invoke(app, ["lint", "--xacro-arg", "novalue", str(path)])
    assert result.exit_code == 2


def test_lint_urdf_alias_and_json(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r">\n<link name="a"/>\n<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>\n</robot>'
    )
    result = CliRunner().invoke(app, ["lint-urdf", "--format", "json", str(path)])
    assert result.exit_code == 1
    doc = json.loads(result.stdout)
    assert doc["schema_version"] == 1
    (finding,) = doc["findings"]
    assert finding["code"] == "U101" and finding["line"] == 3 and finding["severity"] == "error"
    assert set(finding) >= {"path", "line", "column", "code", "name", "severity", "message", "fix"}
