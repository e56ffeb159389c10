"""Real ROS workspace layouts (issue 10): MoveIt configs, SRDF xacros, macro libraries, non-MoveIt
kinematics.yaml, kinematics-only models, xacro failures inside includes. Each test builds a small
workspace of its own in tmp_path, shaped like the real packages it stands for."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding, Severity

X = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'


def arm_urdf(name: str = "arm", *, inertial: bool = True, effort: str = "10", joints: int = 2) -> str:
    links = ['<link name="base_link"/>']  # KDL ignores a root link's inertia (U402)
    body = []
    for i in range(1, joints + 1):
        parent = "base_link" if i == 1 else f"link{i - 1}"
        links.append(f'<link name="link{i}">{INERTIAL if inertial else ""}</link>')
        body.append(
            f'<joint name="joint{i}" type="revolute"><parent link="{parent}"/><child link="link{i}"/>'
            f'<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="{effort}" velocity="1"/></joint>'
        )
    return f'<robot name="{name}">\n' + "\n".join(links + body) + "\n</robot>\n"


SRDF_BODY = """  <group name="arm"><chain base_link="base_link" tip_link="link2"/></group>
  <group_state name="home" group="arm"><joint name="joint1" value="0"/><joint name="joint2" value="0"/></group_state>
  <disable_collisions link1="base_link" link2="link1" reason="Adjacent"/>
"""
SRDF = f'<?xml version="1.0"?>\n<robot name="arm">\n{SRDF_BODY}</robot>\n'
ROS2_CONTROL = f"""<?xml version="1.0"?>
<robot {X}>
  <xacro:macro name="arm_ros2_control" params="name">
    <ros2_control name="${{name}}" type="system"><joint name="joint1"/></ros2_control>
  </xacro:macro>
</robot>
"""
KINEMATICS = (
    "arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  kinematics_solver_timeout: 0.005\n"
)


def package(directory: Path, name: str) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "package.xml").write_text(f"<package format='3'><name>{name}</name></package>")
    return directory


def lint(*paths: Path, **options: object) -> list[Finding]:
    return lint_paths(list(paths), LintOptions(**options)).findings  # type: ignore[arg-type]


def severe(findings: list[Finding]) -> list[tuple[str, str, str]]:
    return [(Path(f.path).name, f.code, f.message) for f in findings if f.severity is not Severity.INFO]


# ---- 1: SRDF -> URDF pairing ---------------------------------------------------------------------


def setup_assistant_config(tmp_path: Path) -> Path:
    """What MoveIt 2's Setup Assistant writes: config/arm.srdf beside arm.ros2_control.xacro (no links,
    sorts first) and arm.urdf.xacro."""
    config = package(tmp_path / "arm_moveit_config", "arm_moveit_config") / "config"
    config.mkdir()
    (config / "arm.srdf").write_text(SRDF)
    (config / "arm.ros2_control.xacro").write_text(ROS2_CONTROL)
    (config / "arm.urdf.xacro").write_text(arm_urdf().replace("<robot ", f"<robot {X} "))
    return config


def test_srdf_is_paired_with_the_urdf_xacro_not_the_ros2_control_file(tmp_path: Path) -> None:
    config = setup_assistant_config(tmp_path)
    assert severe(lint(config / "arm.srdf")) == []


def test_srdf_findings_name_the_urdf_they_were_checked_against(tmp_path: Path) -> None:
    config = setup_assistant_config(tmp_path)
    (config / "arm.srdf").write_text(SRDF.replace('link2="link1"', 'link2="link_1"'))
    (f,) = [f for f in lint(config / "arm.srdf") if f.code == "S108"]
    assert "arm.urdf.xacro" in f.message


def test_a_file_without_links_is_never_the_srdfs_urdf(tmp_path: Path) -> None:
    config = setup_assistant_config(tmp_path)
    (config / "arm.urdf.xacro").unlink()
    found = lint(config / "arm.srdf")
    assert [f.code for f in found] == ["S002"]  # not S101/S102/S108 against a robot without links


# ---- 2: .srdf.xacro expanded like URDF xacros --------------------------------------------------------


def srdf_xacro_config(tmp_path: Path) -> Path:
    config = setup_assistant_config(tmp_path)
    (config / "arm_groups.xacro").write_text(
        f'<?xml version="1.0"?>\n<robot {X}>\n  <xacro:macro name="arm_groups" params="prefix">\n'
        + SRDF_BODY.replace('"link2"', '"${prefix}link2"')
        + "  </xacro:macro>\n</robot>\n"
    )
    (config / "arm.srdf.xacro").write_text(
        f'<?xml version="1.0"?>\n<robot name="arm" {X}>\n  <xacro:arg name="prefix" default=""/>\n'
        '  <xacro:include filename="arm_groups.xacro"/>\n  <xacro:arm_groups prefix="$(arg prefix)"/>\n</robot>\n'
    )
    (config / "arm.srdf").unlink()
    return config


def test_srdf_xacro_is_expanded_before_it_is_checked(tmp_path: Path) -> None:
    config = srdf_xacro_config(tmp_path)
    assert severe(lint(config / "arm.srdf.xacro")) == []
    # a wrong argument makes a true defect, reported at the macro call in the file that was linted
    found = [f for f in lint(config / "arm.srdf.xacro", xacro_args={"prefix": "left_"}) if f.code == "S102"]
    assert found and all(Path(f.path).name == "arm.srdf.xacro" and f.line == 5 for f in found)
    assert any("left_link2" in f.message for f in found)


def test_srdf_macro_library_is_not_checked_on_its_own(tmp_path: Path) -> None:
    config = srdf_xacro_config(tmp_path)
    (config / "arm_macro.srdf.xacro").write_text((config / "arm_groups.xacro").read_text())
    assert lint(config / "arm_macro.srdf.xacro") == []


def test_kinematics_yaml_groups_checked_against_an_srdf_xacro(tmp_path: Path) -> None:
    config = srdf_xacro_config(tmp_path)
    (config / "kinematics.yaml").write_text(KINEMATICS)
    assert severe(lint(config / "kinematics.yaml")) == []
    (config / "kinematics.yaml").write_text(KINEMATICS.replace("arm:", "arms:"))
    assert [f.code for f in lint(config / "kinematics.yaml")] == ["K101"]


# ---- 6: include files whose root is not <robot> ----------------------------------------------------------


def test_macro_library_with_another_root_is_not_a_robot(tmp_path: Path) -> None:
    lib = tmp_path / "gripper.urdf.xacro"  # prbt_pg70_support/urdf/pg70.urdf.xacro: <gripper> with macros
    lib.write_text(
        f'<gripper name="pg70" {X}>\n  <xacro:macro name="pg70" params="prefix">\n'
        '    <link name="${prefix}finger"/>\n  </xacro:macro>\n</gripper>\n'
    )
    args = tmp_path / "tcp_offset.xacro"
    args.write_text(
        f'<gripper name="offset" {X}>\n  <xacro:arg name="tcp_offset_xyz" default="0 0 0.1"/>\n</gripper>\n'
    )
    assert lint(lib, args) == []


# ---- 7: kinematics.yaml decided by content --------------------------------------------------------------


def test_ur_calibration_named_kinematics_yaml_is_not_moveits(tmp_path: Path) -> None:
    (tmp_path / "default_kinematics.yaml").write_text(
        "kinematics:\n  shoulder:\n    x: 0\n    y: 0\n    z: 0.1625\n    roll: 0\n    pitch: 0\n    yaw: 0\n"
        "  hash: calib_12345\n"
    )
    (tmp_path / "kinematics.yaml").write_text("a1: 0.025\nc1: 0.4\n")  # Franka-style parameters
    assert lint(tmp_path) == []


def test_moveit_kinematics_yaml_is_still_checked(tmp_path: Path) -> None:
    (tmp_path / "kinematics.yaml").write_text(KINEMATICS.replace("0.005", "0"))
    assert {f.code for f in lint(tmp_path / "kinematics.yaml")} == {"K002", "K103"}


# ---- 9: kinematics-only models --------------------------------------------------------------------------


def test_model_without_any_inertial_is_reported_once_at_info(tmp_path: Path) -> None:
    path = tmp_path / "panda.urdf"
    path.write_text(arm_urdf(inertial=False, joints=3))
    found = lint(path)
    assert [(f.code, f.severity) for f in found] == [("U401", Severity.INFO)]
    assert "kinematics-only" in found[0].message


def test_effort_zero_on_every_joint_is_reported_once_at_info(tmp_path: Path) -> None:
    path = tmp_path / "fanuc.urdf"
    path.write_text(arm_urdf(inertial=False, effort="0", joints=6))
    found = lint(path)
    assert [(f.code, f.severity) for f in found] == [("U401", Severity.INFO)]
    assert 'effort="0"' in found[0].message
    path.write_text(arm_urdf(effort="0", joints=6))  # inertials, but ROS-I's effort placeholders
    assert [(f.code, f.severity) for f in lint(path)] == [("U204", Severity.INFO)]


def test_zero_efforts_beside_real_ones_in_a_model_without_inertials_are_placeholders(tmp_path: Path) -> None:
    # An arm at effort 0 beside a torso at 100 (a mobile manipulator's planning model): no link has
    # an <inertial>, so nothing is simulated and the zeros are placeholders like the inertials.
    path = tmp_path / "mobile_manipulator.urdf"
    text = arm_urdf(inertial=False, effort="0", joints=7).replace('effort="0"', 'effort="100"', 1)
    path.write_text(text)
    found = lint(path)
    assert [(f.code, f.severity) for f in found] == [("U401", Severity.INFO)]
    assert 'no link has an <inertial> and 6 of 7 joints have effort="0"' in found[0].message
    path.write_text(text.replace('effort="0"', 'effort="-5"', 1))  # a negative effort is no placeholder
    assert sorted((f.code, f.severity) for f in lint(path)) == [("U204", Severity.ERROR), ("U401", Severity.INFO)]


def test_one_missing_inertial_or_zero_effort_among_real_ones_stays_reported(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_text(
        arm_urdf()
        .replace(f'<link name="link2">{INERTIAL}</link>', '<link name="link2"/>')
        .replace('effort="10" velocity="1"/></joint>\n</robot>', 'effort="0" velocity="1"/></joint>\n</robot>')
    )
    assert sorted((f.code, f.severity) for f in lint(path)) == [("U204", Severity.ERROR), ("U401", Severity.WARNING)]


# ---- 10: X001 where the linted file leads to the error ---------------------------------------------------


def test_xacro_error_inside_an_include_is_reported_at_the_call_in_the_linted_file(tmp_path: Path) -> None:
    lib = package(tmp_path / "lib_description", "lib_description")
    (lib / "macros.xacro").write_text(
        f'<robot {X}>\n  <xacro:macro name="inner" params="a"><link name="${{a}}"/></xacro:macro>\n'
        '  <xacro:macro name="outer" params="name">\n    <xacro:inner a="${name}" b="1"/>\n  </xacro:macro>\n</robot>\n'
    )
    main = tmp_path / "robot" / "robot.urdf.xacro"
    main.parent.mkdir()
    main.write_text(
        f'<robot name="r" {X}>\n  <xacro:include filename="$(find lib_description)/macros.xacro"/>\n'
        '  <link name="base"/>\n  <xacro:outer name="l1"/>\n</robot>\n'
    )
    (f,) = lint(main)
    assert (Path(f.path).name, f.code, f.line) == ("robot.urdf.xacro", "X001", 4)
    assert f.message.count('Invalid parameter "b"') == 1 and "<class" not in f.message
    assert "macros.xacro:4" in f.message  # where xacro was inside the include


def test_xacro_error_names_the_option_that_supplies_the_missing_piece(tmp_path: Path) -> None:
    main = tmp_path / "robot.urdf.xacro"
    main.write_text(
        f'<robot name="$(arg name)" {X}>\n  <xacro:include filename="$(find missing_pkg)/x.xacro"/>\n</robot>\n'
    )
    (f,) = lint(main)
    assert f.line == 1 and f.hint is not None and "--xacro-arg name:=" in f.hint
    (f,) = lint(main, xacro_args={"name": "r"})
    assert f.line == 2 and "missing_pkg" in f.message and f.hint is not None and "--package-path" in f.hint


# ---- 11: S002 / K002 find the counterpart, or say why not ---------------------------------------------------


def test_setup_assistant_names_the_urdf_in_another_package(tmp_path: Path) -> None:
    description = package(tmp_path / "ws" / "arm_description", "arm_robot_description")
    (description / "robots").mkdir()
    (description / "robots" / "arm.xacro").write_text(
        f'<robot name="arm" {X}>\n  <xacro:arg name="dof" default=""/>\n'
        "  <xacro:if value=\"${'$(arg dof)' != '2'}\"><xacro:undefined_macro/></xacro:if>\n"
        + "\n".join(arm_urdf().splitlines()[1:-1])
        + "\n</robot>\n"
    )
    config_pkg = package(tmp_path / "ws" / "arm_moveit_config", "arm_moveit_config")
    (config_pkg / "config").mkdir()
    (config_pkg / "config" / "arm.srdf").write_text(SRDF)
    (config_pkg / "config" / "kinematics.yaml").write_text(KINEMATICS)
    (config_pkg / "config" / "other.srdf").write_text(SRDF.replace('<robot name="arm">', '<robot name="other">'))
    (config_pkg / ".setup_assistant").write_text(
        "moveit_setup_assistant_config:\n  urdf:\n    package: arm_robot_description\n"
        "    relative_path: robots/arm.xacro\n    xacro_args:\n      dof:=2\n  srdf:\n    relative_path: config/arm.srdf\n"
    )
    assert severe(lint(config_pkg)) == []


def test_s002_says_why_the_urdf_could_not_be_used(tmp_path: Path) -> None:
    config = setup_assistant_config(tmp_path)
    (config / "arm.urdf.xacro").write_text(f'<robot name="arm" {X}><link name="${{missing}}"/></robot>')
    (f,) = lint(config / "arm.srdf")
    assert f.code == "S002" and "arm.urdf.xacro" in f.message and "missing" in f.message


def test_srdf_without_extension_is_recognised_by_content(tmp_path: Path) -> None:
    (tmp_path / "urdf").mkdir()
    (tmp_path / "srdf").mkdir()
    (tmp_path / "urdf" / "robot.xml").write_text(arm_urdf())
    srdf = tmp_path / "srdf" / "robot.xml"  # moveit_resources/pr2_description/srdf/robot.xml
    srdf.write_text(SRDF.replace('<joint name="joint2" value="0"/>', ""))
    (f,) = lint(srdf, urdf=tmp_path / "urdf" / "robot.xml")
    assert f.code == "S107" and "joint2" in f.message


# ---- stdin and `armtool expand` -------------------------------------------------------------------------------


def test_lint_reads_a_robot_description_from_stdin(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(
        app, ["lint", "--format", "json", "-"], input=arm_urdf().replace('velocity="1"', 'velocity="0"', 1)
    )
    assert result.exit_code == 1, result.output
    assert '"U203"' in result.stdout and '"path": "-"' in result.stdout


def test_expand_prints_armtools_expansion(tmp_path: Path) -> None:
    main = tmp_path / "robot.urdf.xacro"
    main.write_text(
        f'<robot name="r" {X}>\n  <xacro:arg name="prefix" default=""/>\n  <link name="$(arg prefix)base"/>\n</robot>\n'
    )
    result = CliRunner().invoke(app, ["expand", str(main), "--xacro-arg", "prefix:=left_"])
    assert result.exit_code == 0 and '<link name="left_base"/>' in result.stdout
    bad = CliRunner().invoke(app, ["expand", str(main.with_name("missing.xacro"))])
    assert isinstance(bad.exception, ArmtoolError)  # main() prints it and exits 2


def test_lint_help_keeps_bracketed_text() -> None:
    result = CliRunner().invoke(app, ["lint", "--help"], env={"COLUMNS": "200"})
    assert "[default: error]" in result.stdout  # rich markup would eat it unescaped
