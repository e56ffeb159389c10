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


DOF_ARM = f"""<?xml version="1.0"?>
<robot name="arm" {X}>
  <xacro:arg name="dof" default="7"/>
  <link name="base"/>
  {joint("j1", "base", "l1")}
  <xacro:if value="${{$(arg dof) == 7}}">{joint("j7", "l1", "l7")}</xacro:if>
  <xacro:unless value="${{$(arg dof) == 7}}">{joint("j6", "l1", "wrist6")}</xacro:unless>
</robot>
"""


def _variant_folders(tmp_path: Path, six: str) -> Path:
    """config/<six>/arm.srdf (written for dof:=6) beside config/7dof/arm.srdf."""
    (tmp_path / "urdf").mkdir()
    (tmp_path / "urdf" / "arm.urdf.xacro").write_text(DOF_ARM)
    for folder, tip in ((six, "wrist6"), ("7dof", "l7")):
        (tmp_path / "config" / folder).mkdir(parents=True)
        (tmp_path / "config" / folder / "arm.srdf").write_text(
            f'<robot name="arm"><group name="arm"><chain base_link="base" tip_link="{tip}"/></group>'
            f'<disable_collisions link1="l1" link2="{tip}" reason="Adjacent"/></robot>\n'
        )
    return tmp_path / "config" / six / "arm.srdf"


def test_an_srdf_in_a_variant_folder_is_checked_against_its_variant(tmp_path: Path) -> None:
    """Issue 27 item 6: config/6dof/ says dof:=6; never names missing from the 7-DoF default."""
    srdf = _variant_folders(tmp_path, "6dof")
    findings = lint_paths([srdf], LintOptions(urdf=tmp_path / "urdf" / "arm.urdf.xacro")).findings
    assert [f.code for f in findings] == []
    broken = srdf.read_text().replace('link2="wrist6"', 'link2="wrist7"')
    srdf.write_text(broken)  # a typo in the 6-DoF SRDF is still one
    findings = lint_paths([srdf], LintOptions(urdf=tmp_path / "urdf" / "arm.urdf.xacro")).findings
    assert [(f.code, "wrist7" in f.message) for f in findings] == [("S108", True)]


def test_an_srdf_in_a_variant_folder_that_names_no_value_could_not_be_checked(tmp_path: Path) -> None:
    srdf = _variant_folders(tmp_path, "short")
    findings = lint_paths([srdf], LintOptions(urdf=tmp_path / "urdf" / "arm.urdf.xacro")).findings
    assert [f.code for f in findings] == ["S003"]
    assert "could not be checked: it sits in the variant folder 'short'" in findings[0].message
    assert "pass --xacro-arg NAME:=VALUE for this variant" in findings[0].message
