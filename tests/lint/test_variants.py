"""Xacro argument variants: the configuration lists several argument sets for one file and each is
linted; an SRDF written for another set is one S003 naming the argument, checked against that set."""

from __future__ import annotations

from pathlib import Path

from armtool.lint.config import load_config
from armtool.lint.engine import LintOptions, lint_paths

X = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'


def joint(name: str, parent: str, child: str) -> str:
    return (
        f'<link name="{child}">{INERTIAL}</link><joint name="{name}" type="revolute"><parent link="{parent}"/>'
        f'<child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    )


GRIPPER_ARM = f"""<?xml version="1.0"?>
<robot name="arm" {X}>
  <xacro:arg name="gripper" default="none"/>
  <link name="base"/>
  {joint("j1", "base", "l1")}
  <xacro:if value="${{'$(arg gripper)' == 'robotiq'}}">
    <xacro:include filename="grippers/robotiq.xacro"/>
  </xacro:if>
</robot>
"""


def test_each_argument_set_is_linted_and_findings_name_their_set(tmp_path: Path) -> None:
    """The gripper option includes a file that does not exist: only its argument set shows it."""
    (tmp_path / "urdf").mkdir()
    (tmp_path / "urdf" / "arm.urdf.xacro").write_text(GRIPPER_ARM)
    assert lint_paths([tmp_path / "urdf"], LintOptions()).findings == []
    (tmp_path / "armtool.toml").write_text(
        '[lint.xacro-args]\n"urdf/arm.urdf.xacro" = [{ gripper = "none" }, { gripper = "robotiq" }]\n'
    )
    config = load_config(tmp_path / "armtool.toml")
    assert config.xacro_arg_sets(tmp_path / "urdf" / "arm.urdf.xacro") == [{"gripper": "none"}, {"gripper": "robotiq"}]
    assert config.xacro_args_for(tmp_path / "urdf" / "arm.urdf.xacro") == {"gripper": "none"}  # other commands
    (finding,) = lint_paths([tmp_path / "urdf"], LintOptions(config=config)).findings
    assert finding.code == "X001" and finding.line == 7
    assert "robotiq.xacro" in finding.message and finding.message.endswith("[xacro args gripper:=robotiq]")


SIX_OR_SEVEN = f"""<?xml version="1.0"?>
<robot name="arm" {X}>
  <xacro:arg name="dof" default="7"/>
  <xacro:property name="dof" value="$(arg dof)"/>
  <link name="base"/>
  {joint("joint_1", "base", "shoulder_link")}
  <xacro:if value="${{dof == 6}}">{joint("joint_2", "shoulder_link", "bicep_link")}</xacro:if>
  <xacro:unless value="${{dof == 6}}">{joint("joint_2", "shoulder_link", "half_arm_link")}</xacro:unless>
</robot>
"""
SIX_DOF_SRDF = """<robot name="arm">
  <group name="arm"><chain base_link="base" tip_link="bicep_link"/></group>
  <disable_collisions link1="shoulder_link" link2="bicep_link" reason="Adjacent"/>
  <disable_collisions link1="base" link2="bicep_link" reason="Never"/>
</robot>
"""


def test_srdf_for_another_variant_is_one_finding_naming_the_argument(tmp_path: Path) -> None:
    urdf = tmp_path / "arm.urdf.xacro"
    urdf.write_text(SIX_OR_SEVEN)
    srdf = tmp_path / "config" / "arm.srdf"
    srdf.parent.mkdir()
    srdf.write_text(SIX_DOF_SRDF)
    (finding,) = lint_paths([srdf], LintOptions(urdf=urdf)).findings  # was one S104 and two S108
    assert finding.code == "S003" and "--xacro-arg dof:=6" in finding.message and "bicep_link" in finding.message
    # the argument given: nothing to report
    assert lint_paths([srdf], LintOptions(urdf=urdf, xacro_args={"dof": "6"})).findings == []
    # a name no variant has is still its own finding (a typo, not a variant)
    srdf.write_text(SIX_DOF_SRDF.replace('link1="base" link2="bicep_link"', 'link1="bse" link2="shoulder_link"'))
    codes = sorted(f.code for f in lint_paths([srdf], LintOptions(urdf=urdf, xacro_args={"dof": "6"})).findings)
    assert codes == ["S108"]


def test_srdf_of_another_robot_is_one_finding_and_not_checked_name_by_name(tmp_path: Path) -> None:
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(f'<robot name="arm">\n<link name="base"/>\n{joint("j1", "base", "l1")}\n</robot>\n')
    srdf = tmp_path / "config" / "arm.srdf"
    srdf.parent.mkdir()
    links = ["torso", "head", "neck", "hip", "knee", "ankle"]
    srdf.write_text(
        '<robot name="arm">\n'
        + "".join(f'<disable_collisions link1="{a}" link2="l1" reason="Never"/>\n' for a in links)
        + "</robot>\n"
    )
    (finding,) = lint_paths([srdf], LintOptions(urdf=urdf)).findings  # was one S108 per link
    assert finding.code == "S003" and "does not describe arm.urdf: 6 of the 7" in finding.message
