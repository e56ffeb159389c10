"""What a lint run checked (armtool.lint.checked, issue 27 What to build 1): per package the URDF,
SRDF and MoveIt files, and the files that could not be paired; "All checks passed" only when
nothing was skipped. The two kinds of package that passed silently: no .setup_assistant, and a
.setup_assistant naming a renamed SRDF (tests/lint/test_setup_assistant.py has that one's M101)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app

ROBOTS = Path(__file__).resolve().parents[2] / "fixtures" / "robots"


def _run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(app, ["lint", *args])
    return result.exit_code, result.stdout


@pytest.fixture
def no_setup_assistant(tmp_path: Path) -> Path:
    """The clean MoveIt package without .setup_assistant, its SRDF moved to srdf/ (hand-written
    packages): MoveItConfigsBuilder's fallbacks (config/<robot>.urdf, config/<robot>.srdf) find neither."""
    shutil.copytree(ROBOTS / "clean_arm", tmp_path / "clean_arm")
    package = tmp_path / "clean_arm_moveit_config"
    shutil.copytree(ROBOTS / "clean_arm_moveit_config", package)
    (package / ".setup_assistant").unlink()
    (package / "srdf").mkdir()
    (package / "config" / "clean_arm.srdf").rename(package / "srdf" / "clean_arm.srdf")
    return package


def test_a_package_without_setup_assistant_is_no_silent_pass(no_setup_assistant: Path, tmp_path: Path) -> None:
    code, out = _run("--moveit-config", str(no_setup_assistant), "--package-path", str(tmp_path))
    assert "All checks passed" not in out and code == 0  # warnings only
    assert out.count("M102") == 2 and "no URDF found for the MoveIt config" in out and "no SRDF found" in out
    assert "pass --urdf PATH" in out and "pass --srdf PATH" in out


def test_the_option_that_fixes_it_checks_the_file(no_setup_assistant: Path, tmp_path: Path) -> None:
    urdf = tmp_path / "clean_arm" / "urdf" / "clean_arm.urdf"
    srdf = no_setup_assistant / "srdf" / "clean_arm.srdf"
    code, out = _run(
        "--moveit-config", str(no_setup_assistant), "--package-path", str(tmp_path), "--urdf", str(urdf),
        "--srdf", str(srdf), "--format", "json",
    )  # fmt: skip
    doc = json.loads(out)
    assert code == 0 and [f["code"] for f in doc["findings"]] == []
    (pkg,) = [p for p in doc["checked"] if p["package"].endswith("clean_arm_moveit_config")]
    assert pkg["srdf"] == [str(srdf)] and pkg["urdf"] == [str(urdf)] and pkg["not_paired"] == []
    assert any(f.endswith("kinematics.yaml") for f in pkg["moveit_files"])


def test_text_names_what_was_checked_and_what_was_not_paired(tmp_path: Path) -> None:
    config = tmp_path / "config"
    config.mkdir()
    (config / "kinematics.yaml").write_text("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n")
    code, out = _run(str(config), "--ignore", "K002")
    assert code == 0 and "checked:" in out and "not paired with an SRDF: kinematics.yaml" in out
    assert "All checks passed" not in out
    assert "No problems in what was checked (1 file); 1 file could not be paired" in out


def test_a_paired_package_passes_and_says_with_what() -> None:
    code, out = _run(str(ROBOTS / "clean_arm" / "urdf"), str(ROBOTS / "clean_arm" / "config"))
    assert code == 0 and "All checks passed (3 files checked)." in out
    assert "URDF urdf/clean_arm.urdf; SRDF config/clean_arm.srdf; config/kinematics.yaml" in out
