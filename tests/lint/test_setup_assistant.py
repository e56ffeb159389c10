"""M101 and the stale `.setup_assistant` (issue 27, What to build 1): an entry naming a missing file
is a finding on its line with the file it became; lint checks the SRDF the package's layout
gives instead of skipping it; ik-bench and the other robot commands say the path came from
`.setup_assistant` (trossen_arm_moveit: config/wxai.srdf, renamed config/wxai.srdf.xacro)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.lint.engine import LintOptions, lint_paths
from armtool.model.packages import PackageResolver
from armtool.moveit.package import read_package

ROBOTS = Path(__file__).resolve().parents[2] / "fixtures" / "robots"


@pytest.fixture
def renamed(tmp_path: Path) -> Path:
    """The clean MoveIt package whose SRDF was renamed to .srdf.xacro after the Setup Assistant ran,
    with a defect in it (group_state out of limits) that only checking the SRDF finds."""
    shutil.copytree(ROBOTS / "clean_arm", tmp_path / "clean_arm")
    package = tmp_path / "clean_arm_moveit_config"
    shutil.copytree(ROBOTS / "clean_arm_moveit_config", package)
    srdf = package / "config" / "clean_arm.srdf"
    srdf.rename(package / "config" / "clean_arm.srdf.xacro")
    return package


def test_m101_on_the_line_with_the_file_it_became(renamed: Path, tmp_path: Path) -> None:
    findings = lint_paths([renamed], LintOptions(package_paths=[tmp_path])).findings
    (hit,) = [f for f in findings if f.code == "M101"]
    assert (Path(hit.path).name, hit.line, hit.severity.value) == (".setup_assistant", 7, "warning")
    assert hit.message == (
        ".setup_assistant names the SRDF config/clean_arm.srdf, which does not exist (did you mean 'clean_arm.srdf.xacro'?)"
    )
    assert hit.hint == "write relative_path: config/clean_arm.srdf.xacro"


def test_moveit_config_checks_the_srdf_the_layout_gives(renamed: Path, tmp_path: Path) -> None:
    pkg = read_package(renamed, PackageResolver([tmp_path]))
    assert pkg.srdf == renamed / "config" / "clean_arm.srdf.xacro"
    assert "does not exist" in pkg.srdf_why
    xacro = renamed / "config" / "clean_arm.srdf.xacro"
    xacro.write_text(xacro.read_text().replace('value="0"', 'value="99"', 1))
    findings = lint_paths([], LintOptions(package_paths=[tmp_path], moveit_config=renamed)).findings
    assert {"M101", "S106"} <= {f.code for f in findings}  # the renamed SRDF was checked, not skipped


def test_ik_bench_says_the_path_came_from_setup_assistant(renamed: Path, tmp_path: Path) -> None:
    (renamed / "config" / "clean_arm.srdf.xacro").rename(renamed / "config" / "other.txt")
    from armtool.cli.options import RobotOptions

    with pytest.raises(ArmtoolError) as caught:
        RobotOptions(None, [tmp_path]).moveit_package(renamed, None, "--urdf")
    assert caught.value.what.startswith("the SRDF that .setup_assistant names, config/clean_arm.srdf, does not exist")
    assert (caught.value.where or "").endswith(".setup_assistant:7")


def test_ik_bench_notes_the_srdf_it_took_instead(renamed: Path, tmp_path: Path) -> None:
    result = CliRunner().invoke(
        app,
        [
            "ik-bench",
            "--moveit-config",
            str(renamed),
            "--package-path",
            str(tmp_path),
            "--group",
            "arm",
            "--samples",
            "3",
            "--solvers",
            "lm",
            "--format",
            "json",
        ],
    )
    assert result.exit_code == 0, result.stderr
    assert (
        "note: .setup_assistant names config/clean_arm.srdf, which does not exist; using config/clean_arm.srdf.xacro"
        in result.stderr
    )
    assert json.loads(result.stdout)["tip"] == "tool0"
