"""SRDF groups → the chain MoveIt's IK plugin would get: joint sets in any order, links, chains, subgroups."""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik.group import group_chain, group_settings

ARM = """<robot name="arm">
  <link name="world"/><link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/>
  <link name="flange"/><link name="tool_frame"/><link name="finger"/>
  <joint name="world_joint" type="fixed"><parent link="world"/><child link="base"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="flange_joint" type="fixed"><parent link="l3"/><child link="flange"/><origin xyz="0 0 0.1"/></joint>
  <joint name="tool_frame_joint" type="fixed"><parent link="flange"/><child link="tool_frame"/><origin xyz="0 0 0.05"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="flange"/><child link="finger"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
</robot>"""


def chain_of(groups: str, group: str = "arm") -> tuple[str, str, tuple[str, ...]]:
    srdf = etree.fromstring(
        f'<robot name="arm"><virtual_joint name="fixed_base" type="fixed" parent_frame="map" child_link="world"/>{groups}</robot>'
    )
    found = group_chain(srdf, group, etree.fromstring(ARM), source="arm.srdf")
    return found.base, found.tip, found.joints


def test_joint_list_is_a_set_ordered_by_the_tree() -> None:
    """Kinova gen3_lite lists its tool frame joint first; MoveIt sorts the set in tree order."""
    group = '<group name="arm"><joint name="tool_frame_joint"/><joint name="j3"/><joint name="j1"/><joint name="j2"/><joint name="flange_joint"/></group>'
    assert chain_of(group) == ("base", "tool_frame", ("j1", "j2", "j3", "flange_joint", "tool_frame_joint"))


def test_fixed_first_joint_sets_the_base_frame() -> None:
    """xArm lists world_joint: MoveIt's base frame is that joint's parent."""
    group = (
        '<group name="arm"><joint name="world_joint"/><joint name="j1"/><joint name="j2"/><joint name="j3"/></group>'
    )
    assert chain_of(group)[:2] == ("world", "l3")


def test_links_chains_and_subgroups() -> None:
    groups = (
        '<group name="upper"><link name="l1"/><link name="l2"/></group>'
        '<group name="arm"><group name="upper"/><chain base_link="l2" tip_link="flange"/></group>'
    )
    assert chain_of(groups) == ("base", "flange", ("j1", "j2", "j3", "flange_joint"))


def test_fixed_virtual_joint_in_group_is_ignored() -> None:
    assert chain_of('<group name="arm"><joint name="fixed_base"/><chain base_link="base" tip_link="l3"/></group>')[
        :2
    ] == ("base", "l3")


def test_not_a_chain_is_refused() -> None:
    with pytest.raises(
        ArmtoolError,
        match="not a serial chain .*tool_frame_joint.* another branch|not a serial chain .*finger_joint.* another branch",
    ):
        chain_of(
            '<group name="arm"><joint name="j1"/><joint name="finger_joint"/><joint name="tool_frame_joint"/></group>'
        )
    with pytest.raises(ArmtoolError, match=r"moving joint\(s\) j2 .* not in the group"):
        chain_of('<group name="arm"><joint name="j1"/><joint name="j3"/></group>')


def test_unknown_names_are_clear() -> None:
    with pytest.raises(ArmtoolError, match="group 'ram' not in arm.srdf.*did you mean 'arm'"):
        chain_of('<group name="arm"><joint name="j1"/></group>', group="ram")
    with pytest.raises(ArmtoolError, match="joint 'j4' is not in the URDF"):
        chain_of('<group name="arm"><joint name="j4"/></group>')
    with pytest.raises(ArmtoolError, match="include each other"):
        chain_of('<group name="a"><group name="arm"/></group><group name="arm"><group name="a"/></group>')


def test_position_only_ik_and_timeout(tmp_path: Path) -> None:
    kin = tmp_path / "kinematics.yaml"
    kin.write_text(
        "arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n"
        "  kinematics_solver_timeout: 0.02\n  position_only_ik: true\nother:\n  kinematics_solver_timeout: 1\n"
    )
    settings = group_settings(kin, "arm")
    assert (settings.timeout_s, settings.position_only) == (0.02, True)
    assert not group_settings(kin, "other").position_only
    kin.write_text("arm:\n  position_only_ik: 3\n")
    with pytest.raises(ArmtoolError, match="position_only_ik of 'arm' is 3"):
        group_settings(kin, "arm")


def test_timeout_beyond_a_floats_range_is_an_input_error(tmp_path: Path) -> None:
    # YAML integers are unbounded: 10**400 seconds is out of range, not an OverflowError traceback.
    kin = tmp_path / "kinematics.yaml"
    kin.write_text("arm:\n  kinematics_solver_timeout: 1" + "0" * 400 + "\n")
    with pytest.raises(ArmtoolError, match="kinematics_solver_timeout of 'arm' is") as info:
        group_settings(kin, "arm")
    assert info.value.where == f"{kin}:2"
