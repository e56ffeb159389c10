"""kinematics.yaml rules K101-K105: the bundled fixtures, then one inline file per case."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding, Severity
from armtool.lint.rules.k102_unknown_solver_plugin import KNOWN_PLUGINS
from tests.lint.helpers import codes

FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "robots" / "clean_arm"

SRDF = """<robot name="arm">
  <group name="arm"><joint name="joint1"/></group>
  <group name="gripper"><joint name="finger_joint"/></group>
</robot>
"""


def lint_yaml(tmp_path: Path, text: str, *, srdf: bool = True) -> list[Finding]:
    """Lint config/kinematics.yaml with SRDF beside it (K002 and the SRDF's own findings left out)."""
    config = tmp_path / "config"
    config.mkdir(exist_ok=True)
    if srdf:
        (config / "arm.srdf").write_text(SRDF, encoding="utf-8")
    path = config / "kinematics.yaml"
    path.write_text(text, encoding="utf-8")
    return [f for f in lint_paths([path], LintOptions()).findings if f.code.startswith("K1")]


def _fixture(*parts: str) -> Path:
    path = FIXTURE.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"fixture {path} not present")
    return path


def test_clean_arm_kinematics_has_no_findings() -> None:
    path = _fixture("config", "kinematics.yaml")
    assert lint_paths([path], LintOptions()).findings == []


def test_broken_arm_kinematics_one_finding_per_defect() -> None:
    found = lint_paths([_fixture("config_broken", "kinematics.yaml")], LintOptions()).findings
    found = [f for f in found if f.path.endswith("kinematics.yaml")]
    assert codes(found) == [("K102", 4), ("K104", 7), ("K101", 9), ("K105", 14), ("K103", 16)]
    k102, k104, k101, k105, k103 = found
    assert "did you mean 'kdl_kinematics_plugin/KDLKinematicsPlugin'" in k102.message
    assert k104.message == "group 'arm': kinematics_solver_timeout 0.0005 s = 0.5 ms; did you mean 0.005 (5 ms)?"
    assert "group 'manipulator' is not defined in clean_arm.srdf" in k101.message
    assert (k105.column, k103.column) == (40, 30)
    assert k103.message == "group 'wrist': kinematics_solver_timeout is -1"


# ---- sound files --------------------------------------------------------------------------------


def test_sound_ros1_file(tmp_path: Path) -> None:
    text = (
        "arm:\n"
        "  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n"
        "  kinematics_solver_search_resolution: 0.005\n"
        "  kinematics_solver_timeout: 0.005\n"
        "  kinematics_solver_attempts: 3\n"
    )
    assert lint_yaml(tmp_path, text) == []


def test_sound_ros2_file(tmp_path: Path) -> None:
    text = (
        "/**:\n"
        "  ros__parameters:\n"
        "    robot_description_kinematics:\n"
        "      arm:\n"
        "        kinematics_solver: pick_ik/PickIkPlugin\n"
        "        kinematics_solver_timeout: 0.05\n"
    )
    assert lint_yaml(tmp_path, text) == []


@pytest.mark.parametrize(
    "plugin",
    [
        *KNOWN_PLUGINS,
        "ur5_arm_ikfast_plugin/IKFastKinematicsPlugin",
        "my_robot_manipulator_kinematics/IKFastKinematicsPlugin",
    ],
)
def test_known_plugins_are_accepted(tmp_path: Path, plugin: str) -> None:
    assert lint_yaml(tmp_path, f"arm:\n  kinematics_solver: {plugin}\n") == []


# ---- K101 ------------------------------------------------------------------------------------------


def test_k101_group_not_in_srdf(tmp_path: Path) -> None:
    found = lint_yaml(
        tmp_path, "arm:\n  kinematics_solver_timeout: 0.005\ngriper:\n  kinematics_solver_timeout: 0.005\n"
    )
    (f,) = found
    assert (f.code, f.line, f.column, f.severity) == ("K101", 3, 1, Severity.ERROR)
    assert f.message == "group 'griper' is not defined in arm.srdf (did you mean 'gripper'?)"
    assert f.hint == "rename the key to 'gripper'"


def test_k101_lists_groups_when_nothing_is_close(tmp_path: Path) -> None:
    (f,) = lint_yaml(tmp_path, "manipulator:\n  kinematics_solver_timeout: 0.005\n")
    assert "did you mean" not in f.message and f.hint == "groups in arm.srdf: arm, gripper"


def test_k101_needs_the_srdf(tmp_path: Path) -> None:
    assert lint_yaml(tmp_path, "manipulator:\n  kinematics_solver_timeout: 0.005\n", srdf=False) == []


# ---- K102 ------------------------------------------------------------------------------------------


def test_k102_typo_in_plugin(tmp_path: Path) -> None:
    (f,) = lint_yaml(tmp_path, "arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicPlugin\n")
    assert (f.code, f.line, f.column) == ("K102", 2, 22)
    assert "kinematics_solver 'kdl_kinematics_plugin/KDLKinematicPlugin' is not a known IK plugin" in f.message
    assert "did you mean 'kdl_kinematics_plugin/KDLKinematicsPlugin'" in f.message


def test_k102_trac_ik_spelling(tmp_path: Path) -> None:
    (f,) = lint_yaml(tmp_path, "arm:\n  kinematics_solver: trac_ik_kinematics_plugin/TracIKKinematicsPlugin\n")
    assert "did you mean 'trac_ik_kinematics_plugin/TRAC_IKKinematicsPlugin'" in f.message


def test_k102_unknown_plugin_without_suggestion(tmp_path: Path) -> None:
    (f,) = lint_yaml(tmp_path, "arm:\n  kinematics_solver: my_solver\n")
    assert "did you mean" not in f.message and f.hint is not None and "ignore[K102]" in f.hint


# ---- K103 / K104 -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "value, shown",
    [
        ("0", "is 0"),
        ("-0.005", "is -0.005"),
        ("fast", "is 'fast', not a number"),
        ("'0.005'", "is '0.005', not a number"),
        ("true", "is True, not a number"),
    ],
)
def test_k103_non_positive_or_not_a_number(tmp_path: Path, value: str, shown: str) -> None:
    (f,) = lint_yaml(tmp_path, f"arm:\n  kinematics_solver_timeout: {value}\n")
    assert (f.code, f.line, f.column, f.severity) == ("K103", 2, 30, Severity.ERROR)
    assert f.message == f"group 'arm': kinematics_solver_timeout {shown}"


def test_k104_sub_millisecond_timeout(tmp_path: Path) -> None:
    (f,) = lint_yaml(tmp_path, "arm:\n  kinematics_solver_timeout: 0.0005\n")
    assert (f.code, f.line, f.severity) == ("K104", 2, Severity.WARNING)
    assert f.message == "group 'arm': kinematics_solver_timeout 0.0005 s = 0.5 ms; did you mean 0.005 (5 ms)?"


@pytest.mark.parametrize("value", ["0.001", "0.005", "1", "10"])
def test_k104_one_millisecond_and_more_is_fine(tmp_path: Path, value: str) -> None:
    assert lint_yaml(tmp_path, f"arm:\n  kinematics_solver_timeout: {value}\n") == []


def test_k104_ros2_layout(tmp_path: Path) -> None:
    text = "/**:\n  ros__parameters:\n    robot_description_kinematics:\n      arm:\n        kinematics_solver_timeout: 0.0001\n"
    (f,) = lint_yaml(tmp_path, text)
    assert (f.code, f.line, f.column) == ("K104", 5, 36)
    assert "0.0001 s = 0.1 ms; did you mean 0.001 (1 ms)?" in f.message


# ---- K105 ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("value", ["0", "-0.1", "fine", "[0.005]"])
def test_k105_non_positive_search_resolution(tmp_path: Path, value: str) -> None:
    (f,) = lint_yaml(tmp_path, f"arm:\n  kinematics_solver_search_resolution: {value}\n")
    assert (f.code, f.line, f.column, f.severity) == ("K105", 2, 40, Severity.ERROR)
    assert "kinematics_solver_search_resolution" in f.message


def test_attempts_is_accepted_silently(tmp_path: Path) -> None:
    assert lint_yaml(tmp_path, "arm:\n  kinematics_solver_attempts: 10\n") == []


def test_codes_helper_on_several_findings(tmp_path: Path) -> None:
    text = (
        "arm:\n"
        "  kinematics_solver: kdl_kinematics_plugin/KDL\n"
        "  kinematics_solver_timeout: 0.0005\n"
        "  kinematics_solver_search_resolution: 0\n"
        "hand:\n"
        "  kinematics_solver_timeout: 0\n"
    )
    assert codes(lint_yaml(tmp_path, text)) == [("K102", 2), ("K104", 3), ("K105", 4), ("K101", 5), ("K103", 6)]


@pytest.mark.parametrize(
    "plugin",
    [
        "moveit_opw_kinematics_plugin/MoveItOPWKinematicsPlugin",
        "prbt_manipulator/IKFastKinematicsPlugin",  # an IKFast plugin of any name
        "fanuc_m10ia_ikfast_manipulator_plugin::IKFastKinematicsPlugin",
        "pick_ik/PickIkPlugin",
        "bio_ik/BioIKKinematicsPlugin",
        "cached_ik_kinematics_plugin/CachedKDLKinematicsPlugin",
        "lma_kinematics_plugin/LMAKinematicsPlugin",
        "srv_kinematics_plugin/SrvKinematicsPlugin",
        "my_robot_kinematics/MyAnalyticPlugin",  # a plugin of the workspace: pluginlib's package/Class pattern
    ],
)
def test_k102_real_plugins_pass(tmp_path: Path, plugin: str) -> None:
    assert lint_yaml(tmp_path, f"arm:\n  kinematics_solver: {plugin}\n") == []


@pytest.mark.parametrize(
    "plugin, meant",
    [
        ("kdl_kinematic_plugin/KDLKinematicsPlugin", "kdl_kinematics_plugin/KDLKinematicsPlugin"),
        ("pick_ik/PickIKPlugin", "pick_ik/PickIkPlugin"),
        ("trac_ik_kinematics_plugin/KDLKinematicsPlugin", "trac_ik_kinematics_plugin/TRAC_IKKinematicsPlugin"),
    ],
)
def test_k102_near_misses_are_reported_with_the_real_name(tmp_path: Path, plugin: str, meant: str) -> None:
    (f,) = lint_yaml(tmp_path, f"arm:\n  kinematics_solver: {plugin}\n")
    assert f.code == "K102" and f"did you mean '{meant}'" in f.message


def test_k102_no_unrelated_suggestion(tmp_path: Path) -> None:
    (f,) = lint_yaml(tmp_path, "arm:\n  kinematics_solver: OPW\n")  # not a pluginlib name at all
    assert f.code == "K102" and "did you mean" not in f.message


def test_k002_hint_names_the_real_cause(tmp_path: Path) -> None:
    """The SRDF was found but needs a xacro argument: the hint says so, not "pass --srdf"."""
    config = tmp_path / "config"
    config.mkdir()
    (config / "arm.srdf.xacro").write_text(
        '<robot name="$(arg name)" xmlns:xacro="http://www.ros.org/wiki/xacro"><group name="arm"/></robot>\n'
    )
    (config / "kinematics.yaml").write_text("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n")
    (k002,) = [f for f in lint_paths([config / "kinematics.yaml"], LintOptions()).findings if f.code == "K002"]
    assert "arm.srdf.xacro could not be loaded" in k002.message
    assert k002.hint is not None and "arm.srdf.xacro was found but cannot be used" in k002.hint
    assert "--xacro-arg name:=VALUE" in k002.hint and "--srdf" not in k002.hint


@pytest.mark.parametrize(
    ("other", "expected"),
    [
        (SRDF, []),  # an exported copy: the same groups
        (SRDF.replace('name="gripper"', 'name="hand"'), []),  # another SRDF that also defines group arm
        (SRDF.replace('name="arm"><joint', 'name="arm6"><joint'), []),  # only arm.srdf defines arm: that one
    ],
)
def test_k002_several_srdfs_beside_it_that_define_its_groups(
    tmp_path: Path, other: str, expected: list[tuple[str, int]]
) -> None:
    """Issue 27 item 5: several SRDFs beside a kinematics.yaml are no reason to skip the check when
    they define its groups (panda_ign_moveit2: panda.srdf and panda.srdf.xacro)."""
    config = tmp_path / "config"
    config.mkdir()
    (config / "other.srdf").write_text(other, encoding="utf-8")
    found = lint_yaml(tmp_path, "arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n")
    assert codes(found) == expected
    every = lint_paths([config / "kinematics.yaml"], LintOptions()).findings
    assert [f.code for f in every if f.code == "K002"] == []


def test_k002_several_srdfs_none_of_which_defines_its_groups(tmp_path: Path) -> None:
    config = tmp_path / "config"
    config.mkdir()
    (config / "other.srdf").write_text(SRDF.replace('name="arm"><joint', 'name="arm6"><joint'), encoding="utf-8")
    (config / "arm.srdf").write_text(SRDF.replace('name="arm"><joint', 'name="arm7"><joint'), encoding="utf-8")
    path = config / "kinematics.yaml"
    path.write_text("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n", encoding="utf-8")
    (hit,) = [f for f in lint_paths([path], LintOptions()).findings if f.code == "K002"]
    assert "several SRDFs beside it: arm.srdf, other.srdf" in hit.message
