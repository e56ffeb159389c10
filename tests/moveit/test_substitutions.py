"""ROS 1 launch substitutions in a MoveIt package's YAML files (armtool.moveit.substitutions): the
values come from the launch files that load the file with subst_value, else from the package's
SRDF xacro defaults; kinematics.yaml's groups, controllers' joints and ik-bench read them so
(franka_ros's panda_moveit_config: `$(arg arm_id)_arm`, arm_id default panda)."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.lint.engine import LintOptions, lint_paths
from armtool.moveit.substitutions import launch_values, xacro_arg_defaults

SRDF = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="panda">
  <xacro:arg name="arm_id" default="panda"/>
  <xacro:arg name="hand" default="false"/>
  <group name="$(arg arm_id)_arm"><chain base_link="$(arg arm_id)_link0" tip_link="$(arg arm_id)_link2"/></group>
  <xacro:if value="$(arg hand)">
    <group name="$(arg arm_id)_manipulator"><chain base_link="$(arg arm_id)_link0" tip_link="$(arg arm_id)_link2"/></group>
  </xacro:if>
</robot>
"""
URDF = """<robot name="panda">
  <link name="panda_link0"/><link name="panda_link1"/><link name="panda_link2"/>
  <joint name="panda_joint1" type="revolute"><parent link="panda_link0"/><child link="panda_link1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  <joint name="panda_joint2" type="revolute"><parent link="panda_link1"/><child link="panda_link2"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""
KINEMATICS = """$(arg arm_id)_arm: &arm
  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin
  kinematics_solver_timeout: 0.05
$(arg arm_id)_manipulator: *arm
"""
LAUNCH = """<launch>
  <arg name="arm_id" default="{arm_id}"/>
  <group ns="robot_description_kinematics">
    <rosparam command="load" file="$(find panda_moveit_config)/config/kinematics.yaml" subst_value="true"/>
  </group>
</launch>
"""


def _package(tmp_path: Path, kinematics: str = KINEMATICS) -> Path:
    pkg = tmp_path / "panda_moveit_config"
    (pkg / "config").mkdir(parents=True)
    (pkg / "package.xml").write_text(
        "<package><name>panda_moveit_config</name><buildtool_depend>catkin</buildtool_depend></package>"
    )
    (pkg / "config" / "panda.srdf.xacro").write_text(SRDF)
    (pkg / "config" / "panda.urdf").write_text(URDF)
    (pkg / "config" / "kinematics.yaml").write_text(kinematics)
    return pkg


def test_values_come_from_the_launch_file_that_loads_the_file_with_subst_value(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    kinematics = pkg / "config" / "kinematics.yaml"
    assert launch_values(kinematics) == {"arm_id": "panda", "hand": "false"}  # the SRDF xacro's defaults
    (pkg / "launch").mkdir()
    (pkg / "launch" / "planning_context.launch").write_text(LAUNCH.format(arm_id="fr3"))
    (pkg / "launch" / "other.launch").write_text('<launch><arg name="arm_id" default="nope"/></launch>')
    from armtool.moveit import substitutions

    substitutions._values.cache_clear()
    assert launch_values(kinematics)["arm_id"] == "fr3"  # the launch file's default wins; other.launch loads nothing


def test_xacro_arg_defaults_keep_literals_only(tmp_path: Path) -> None:
    path = tmp_path / "a.srdf.xacro"
    path.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:arg name="a" default="1"/>'
        '<xacro:arg name="b" default="$(arg a)"/><xacro:arg name="c"/></robot>'
    )
    assert xacro_arg_defaults(path) == {"a": "1"}


def test_kinematics_groups_are_read_with_the_substitutions_and_variants(tmp_path: Path) -> None:
    """`$(arg arm_id)_arm` is panda_arm; `$(arg arm_id)_manipulator` exists with hand:=true, which
    the SRDF xacro's flag writes down: no K101. A group no variant defines is still reported."""
    pkg = _package(tmp_path)
    findings = lint_paths([pkg / "config" / "kinematics.yaml"], LintOptions()).findings
    assert [f.code for f in findings] == []
    (pkg / "config" / "kinematics.yaml").write_text(KINEMATICS + "$(arg arm_id)_arn: *arm\n")
    (hit,) = lint_paths([pkg / "config" / "kinematics.yaml"], LintOptions()).findings
    assert (hit.code, hit.line) == ("K101", 5)
    assert hit.message.startswith("group '$(arg arm_id)_arn' (panda_arn) is not defined in panda.srdf.xacro")


def test_controllers_joints_are_read_with_the_substitutions(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    (pkg / ".setup_assistant").write_text(
        "moveit_setup_assistant_config:\n  SRDF:\n    relative_path: config/panda.srdf.xacro\n"
    )
    (pkg / "config" / "simple_moveit_controllers.yaml").write_text(
        "controller_list:\n  - name: arm_controller\n    action_ns: follow_joint_trajectory\n"
        "    type: FollowJointTrajectory\n    joints: [$(arg arm_id)_joint1, $(arg arm_id)_joint2]\n"
    )
    findings = lint_paths([pkg / "config"], LintOptions(urdf=pkg / "config" / "panda.urdf")).findings
    assert [f.code for f in findings if f.code.startswith("C")] == []


def test_ik_bench_reads_the_group_settings_with_the_substitutions(tmp_path: Path) -> None:
    from armtool.ik.group import group_settings, kinematics_groups

    kinematics = _package(tmp_path) / "config" / "kinematics.yaml"
    assert kinematics_groups(kinematics) == ["panda_arm", "panda_manipulator"]
    assert group_settings(kinematics, "panda_manipulator").timeout_s == pytest.approx(0.05)
