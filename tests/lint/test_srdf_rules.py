"""SRDF rules S101-S109: the bundled clean/broken fixtures, then one inline SRDF per case."""

from __future__ import annotations

import glob
import sys
from pathlib import Path

import pytest

from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding, Severity
from tests.lint.helpers import LINK, codes, robot

FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "robots" / "clean_arm"

# A 3-axis arm with a flange and a two-finger gripper (the right finger mimics the left one).
ARM_URDF = robot(
    "\n".join(
        [LINK.format(name=n) for n in ("base_link", "link1", "link2", "link3", "tool0", "left_finger", "right_finger")]
        + [
            '<joint name="joint1" type="revolute"><parent link="base_link"/><child link="link1"/>'
            '<axis xyz="0 0 1"/><limit lower="-3.14" upper="3.14" effort="10" velocity="1"/></joint>',
            '<joint name="joint2" type="revolute"><parent link="link1"/><child link="link2"/>'
            '<axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="10" velocity="1"/></joint>',
            '<joint name="joint3" type="continuous"><parent link="link2"/><child link="link3"/><axis xyz="0 0 1"/></joint>',
            '<joint name="flange" type="fixed"><parent link="link3"/><child link="tool0"/></joint>',
            '<joint name="left_finger_joint" type="prismatic"><parent link="tool0"/><child link="left_finger"/>'
            '<axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="10" velocity="0.1"/></joint>',
            '<joint name="right_finger_joint" type="prismatic"><parent link="tool0"/><child link="right_finger"/>'
            '<axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="10" velocity="0.1"/>'
            '<mimic joint="left_finger_joint"/></joint>',
        ]
    )
)

ARM = '<group name="arm"><chain base_link="base_link" tip_link="tool0"/></group>'
HAND = '<group name="hand"><joint name="left_finger_joint"/><joint name="right_finger_joint"/></group>'
EEF = '<end_effector name="eef" group="hand" parent_link="tool0" parent_group="arm"/>'


def lint_srdf(tmp_path: Path, *lines: str, urdf: bool = True) -> list[Finding]:
    """Lint an SRDF whose line N+1 is lines[N-1] (line 1 is <robot>), against ARM_URDF."""
    options = LintOptions()
    if urdf:
        options.urdf = tmp_path / "arm.urdf"
        options.urdf.write_text(ARM_URDF, encoding="utf-8")
    # in a directory of its own, so that URDF discovery cannot find other tests' files
    path = tmp_path / "config" / "arm.srdf"
    path.parent.mkdir(exist_ok=True)
    path.write_text('<robot name="arm">\n' + "\n".join(lines) + "\n</robot>\n", encoding="utf-8")
    return [f for f in lint_paths([path], options).findings if f.code.startswith("S1")]


def only(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code]


# ---- fixtures ----------------------------------------------------------------------------------


def _fixture(*parts: str) -> Path:
    path = FIXTURE.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"fixture {path} not present")
    return path


def test_clean_arm_srdf_has_no_findings() -> None:
    srdf = _fixture("config", "clean_arm.srdf")
    assert lint_paths([srdf], LintOptions()).findings == []


def test_broken_arm_srdf_one_finding_per_defect() -> None:
    found = lint_paths([_fixture("config_broken", "clean_arm.srdf")], LintOptions()).findings
    assert codes(found) == [
        ("S109", 7),  # left_finger_joint inside the IK group 'arm'
        ("S101", 11),  # joint7
        ("S102", 13),  # link9
        ("S104", 17),  # chain link3 -> base_link
        ("S107", 29),  # bad_home lacks joint6
        ("S106", 30),  # joint4 = 4.0 outside [-3, 3]
        ("S105", 34),  # parent_link 'flange' unknown
        ("S105", 36),  # parent_link link2 outside parent_group wrist
        ("S108", 38),  # lnik2
    ]
    by_line = {f.line: f for f in found}
    assert "did you mean 'joint6'" in by_line[11].message
    assert "did you mean 'link6'" in by_line[13].message
    assert by_line[17].hint == 'swap them: base_link="base_link" tip_link="link3"'
    assert "'joint4' = 4 is outside its limits [-3, 3] rad" in by_line[30].message
    assert by_line[34].hint is not None and 'parent_link="tool0"' in by_line[34].hint
    assert "not a link of parent_group 'wrist'" in by_line[36].message
    assert "did you mean 'link2'" in by_line[38].message
    assert by_line[38].column == 37  # the link2 attribute


# ---- a sound SRDF ----------------------------------------------------------------------------------


def test_sound_srdf_has_no_findings(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<virtual_joint name="world_joint" type="fixed" parent_frame="world" child_link="base_link"/>',
        ARM,
        HAND,
        '<group name="arm_and_hand"><group name="arm"/><group name="hand"/></group>',
        EEF,
        '<group_state name="home" group="arm"><joint name="joint1" value="0"/><joint name="joint2" value="1.5"/>'
        '<joint name="joint3" value="12.0"/></group_state>',
        '<group_state name="open" group="hand"><joint name="left_finger_joint" value="0.04"/></group_state>',
        '<disable_collisions link1="left_finger" link2="right_finger" reason="Never"/>',
        '<passive_joint name="world_joint"/>',
    )
    assert found == []


def test_without_urdf_only_group_names_are_checked(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<group name="arm"><joint name="nope"/><chain base_link="x" tip_link="y"/></group>',
        '<group_state name="home" group="arm"><joint name="nope" value="99"/></group_state>',
        '<end_effector name="eef" group="hnd" parent_link="nowhere"/>',
        urdf=False,
    )
    assert codes(found) == [("S103", 4)]


# ---- S101 ----------------------------------------------------------------------------------------


def test_s101_group_joint_typo_suggests_closest(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, '<group name="arm"><joint name="joint_2"/></group>')
    assert (f.code, f.line, f.column) == ("S101", 2, 26)  # the name attribute
    assert f.severity is Severity.ERROR
    assert "group 'arm': joint 'joint_2' is not in arm.urdf (did you mean 'joint2'?)" == f.message
    assert f.hint is not None and 'name="joint2"' in f.hint


def test_s101_passive_joint_and_group_state_joint(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        ARM,
        '<passive_joint name="jiont3"/>',
        '<group_state name="home" group="arm"><joint name="joint1" value="0"/><joint name="joint2" value="0"/>'
        '<joint name="joint3" value="0"/><joint name="elbow" value="0"/></group_state>',
    )
    assert codes(only(found, "S101")) == [("S101", 3), ("S101", 4)]
    assert "passive_joint: joint 'jiont3'" in found[0].message and "did you mean 'joint3'" in found[0].message
    assert "group_state 'home': joint 'elbow'" in only(found, "S101")[1].message


def test_s101_virtual_joint_is_known(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<virtual_joint name="root_joint" type="floating" parent_frame="world" child_link="base_link"/>',
        '<group name="body"><joint name="root_joint"/><joint name="joint1"/></group>',
    )
    assert only(found, "S101") == []


def test_s101_undeclared_floating_root_hints_virtual_joint(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<group name="body"><joint name="joint1"/></group>',
        '<group_state name="stand" group="body"><joint name="root_joint" value="0 0 0.5 0 0 0 1"/>'
        '<joint name="joint1" value="0"/></group_state>',
    )
    (f,) = only(found, "S101")
    assert f.line == 3 and "did you mean" not in f.message
    assert f.hint is not None and '<virtual_joint name="root_joint" type="floating"' in f.hint
    assert 'child_link="base_link"' in f.hint


# ---- S102 ----------------------------------------------------------------------------------------


def test_s102_link_chain_and_virtual_joint(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<virtual_joint name="w" type="fixed" parent_frame="world" child_link="base"/>',
        '<group name="arm"><chain base_link="base_link" tip_link="tool_0"/></group>',
        '<group name="hand"><link name="left_fingr"/></group>',
    )
    assert codes(found) == [("S102", 2), ("S102", 3), ("S102", 4)]
    assert "virtual_joint 'w': child_link 'base' is not in arm.urdf (did you mean 'base_link'?)" == found[0].message
    assert "chain tip_link 'tool_0'" in found[1].message and "did you mean 'tool0'" in found[1].message
    assert found[1].column == 48  # the tip_link attribute
    assert "group 'hand': link 'left_fingr'" in found[2].message and "did you mean 'left_finger'" in found[2].message


def test_s102_unknown_base_without_close_name_lists_links_above_tip(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, '<group name="arm"><chain base_link="world" tip_link="link3"/></group>')
    assert f.code == "S102" and f.hint is not None and "base_link, link1, link2" in f.hint


# ---- S103 ----------------------------------------------------------------------------------------


def test_s103_subgroup_end_effector_and_group_state(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        ARM,
        HAND,
        '<group name="both"><group name="arm"/><group name="hnd"/></group>',
        '<end_effector name="eef" group="hand" parent_link="tool0" parent_group="manipulator"/>',
        '<group_state name="home" group="arms"><joint name="joint1" value="0"/></group_state>',
    )
    assert codes(found) == [("S103", 4), ("S103", 5), ("S103", 6)]
    assert "group 'both': subgroup 'hnd' is not defined in this SRDF (did you mean 'hand'?)" == found[0].message
    assert "parent_group 'manipulator'" in found[1].message
    assert "group_state 'home': group 'arms'" in found[2].message and "did you mean 'arm'" in found[2].message


def test_s103_suggests_group_that_starts_with_the_name(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<group name="lf_leg"><joint name="joint1"/></group>',
        '<group name="legs"><group name="lf"/></group>',
    )
    (f,) = only(found, "S103")
    assert "did you mean 'lf_leg'" in f.message


# ---- S104 ----------------------------------------------------------------------------------------


def test_s104_reversed_chain_suggests_swap(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, '<group name="arm"><chain base_link="tool0" tip_link="base_link"/></group>')
    assert (f.code, f.line, f.severity) == ("S104", 2, Severity.ERROR)
    assert "chain tip_link 'base_link' is not below base_link 'tool0'" in f.message
    assert f.hint == 'swap them: base_link="base_link" tip_link="tool0"'


def test_s104_sideways_chain_names_common_ancestor(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, '<group name="pinch"><chain base_link="left_finger" tip_link="right_finger"/></group>')
    assert f.code == "S104" and "'tool0'" in f.message
    assert f.hint == 'start the chain where the branches meet: base_link="tool0"'
    # MoveIt's RobotModel::addJointModelGroup builds such a group through the common ancestor
    # (it loads and plans); only chain IK plugins reject it: a warning, not an error.
    assert f.severity == Severity.WARNING


def test_s104_chain_to_itself(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, '<group name="arm"><chain base_link="link2" tip_link="link2"/></group>')
    assert f.code == "S104" and "no joints" in f.message


def test_s104_unknown_links_are_left_to_s102(tmp_path: Path) -> None:
    found = lint_srdf(tmp_path, '<group name="arm"><chain base_link="tool0" tip_link="bse"/></group>')
    assert codes(found) == [("S102", 2)]


# ---- S105 ----------------------------------------------------------------------------------------


def test_s105_parent_link_unknown(tmp_path: Path) -> None:
    found = lint_srdf(tmp_path, ARM, HAND, '<end_effector name="eef" group="hand" parent_link="tool_0"/>')
    (f,) = found
    assert (f.code, f.line) == ("S105", 4)
    assert "end_effector 'eef': parent_link 'tool_0' is not a link in arm.urdf (did you mean 'tool0'?)" == f.message


def test_s105_parent_link_names_a_joint(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, ARM, HAND, '<end_effector name="eef" group="hand" parent_link="flange"/>')
    assert f.code == "S105" and "'flange' is a joint; its child link is 'tool0'" in f.message


def test_s105_parent_link_outside_parent_group(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<group name="arm"><chain base_link="base_link" tip_link="link2"/></group>',
        HAND,
        '<end_effector name="eef" group="hand" parent_link="tool0" parent_group="arm"/>',
    )
    (f,) = found
    assert (f.code, f.line) == ("S105", 4)
    assert "parent_link 'tool0' is not a link of parent_group 'arm'" in f.message
    assert f.hint is not None and 'parent_link="link2"' in f.hint


def test_s105_missing_parent_link(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, ARM, HAND, '<end_effector name="eef" group="hand"/>')
    assert f.code == "S105" and "has no parent_link" in f.message


# ---- S106 ----------------------------------------------------------------------------------------


def _state(*joints: str) -> str:
    body = "".join(f'<joint name="{n}" value="{v}"/>' for n, v in (j.split("=") for j in joints))
    return f'<group_state name="home" group="arm">{body}</group_state>'


def test_s106_value_outside_limits(tmp_path: Path) -> None:
    found = lint_srdf(tmp_path, ARM, _state("joint1=0", "joint2=1.6", "joint3=0"))
    (f,) = found
    assert (f.code, f.line, f.severity) == ("S106", 3, Severity.ERROR)
    assert f.message.startswith("group_state 'home': joint 'joint2' = 1.6 is outside its limits [-1.5, 1.5] rad")
    assert f.message.endswith("arm.urdf)")  # names the URDF it was checked against


def test_s106_degrees_typed_for_radians(tmp_path: Path) -> None:
    (f,) = lint_srdf(tmp_path, ARM, _state("joint1=90", "joint2=0", "joint3=0"))
    assert f.code == "S106" and f.hint is not None and "90 degrees is 1.5708" in f.hint


def test_s106_tolerance_and_continuous(tmp_path: Path) -> None:
    assert lint_srdf(tmp_path, ARM, _state("joint1=3.1400005", "joint2=-1.5000009", "joint3=100")) == []


def test_s106_prismatic_in_metres(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        HAND,
        '<group_state name="open" group="hand"><joint name="left_finger_joint" value="40"/></group_state>',
    )
    (f,) = found
    assert "= 40 is outside its limits [0, 0.04] m" in f.message
    assert f.hint is not None and "40 mm is 0.04" in f.hint


def test_s106_value_not_a_number(tmp_path: Path) -> None:
    found = lint_srdf(tmp_path, ARM, _state("joint1=zero", "joint2=0 0", "joint3=0"))
    assert codes(found) == [("S106", 3), ("S106", 3)]
    assert "joint 'joint1' has value 'zero', not a number" in found[0].message
    assert "joint 'joint2' has value '0 0', not a number" in found[1].message


# ---- S107 ----------------------------------------------------------------------------------------


def test_s107_missing_joint(tmp_path: Path) -> None:
    found = lint_srdf(tmp_path, ARM, _state("joint1=0", "joint3=0"))
    (f,) = found
    assert (f.code, f.line, f.severity) == ("S107", 3, Severity.WARNING)
    assert f.message.startswith("group_state 'home' gives no value for joint of group 'arm': 'joint2' (URDF: ")


def test_s107_skips_fixed_mimic_and_passive_joints(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<group name="arm"><chain base_link="base_link" tip_link="right_finger"/></group>',
        '<passive_joint name="joint3"/>',
        _state("joint1=0", "joint2=0"),
    )
    assert only(found, "S107") == []


# ---- S108 ----------------------------------------------------------------------------------------


def test_s108_unknown_link_in_disable_collisions(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<disable_collisions link1="link1" link2="lnk2" reason="Adjacent"/>',
        '<disable_collisions link1="camera" link2="link2" reason="Never"/>',
    )
    assert codes(found) == [("S108", 2), ("S108", 3)]
    assert found[0].severity is Severity.WARNING
    assert found[0].message == "disable_collisions link2 'lnk2' is not in arm.urdf (did you mean 'link2'?)"
    assert found[0].column == 35  # the link2 attribute
    assert "did you mean" not in found[1].message


# ---- S109 ----------------------------------------------------------------------------------------


def test_s109_chain_ending_at_a_finger(tmp_path: Path) -> None:
    found = lint_srdf(tmp_path, '<group name="arm"><chain base_link="base_link" tip_link="left_finger"/></group>')
    (f,) = found
    assert (f.code, f.line, f.severity) == ("S109", 2, Severity.WARNING)
    assert "group 'arm' is used for IK (it holds a chain) but contains gripper joint 'left_finger_joint'" in f.message


def test_s109_end_effector_group_member_is_a_finger_whatever_its_name(tmp_path: Path) -> None:
    urdf_names = ARM_URDF.replace("left_finger_joint", "j5").replace("right_finger_joint", "j6")
    (tmp_path / "arm.urdf").write_text(urdf_names, encoding="utf-8")
    srdf = tmp_path / "arm.srdf"
    srdf.write_text(
        '<robot name="arm">\n'
        '<group name="manipulator"><joint name="joint1"/><joint name="joint2"/><joint name="joint3"/><joint name="j5"/></group>\n'
        '<group name="gripper"><joint name="j5"/><joint name="j6"/></group>\n'
        '<end_effector name="eef" group="gripper" parent_link="tool0"/>\n'
        "</robot>\n",
        encoding="utf-8",
    )
    found = lint_paths([srdf], LintOptions(urdf=tmp_path / "arm.urdf")).findings
    (f,) = only(found, "S109")
    assert f.line == 2 and "its name says arm" in f.message and "'j5' (in end effector group 'gripper')" in f.message


def test_s109_leaves_hand_and_composite_groups_alone(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        ARM,
        HAND,
        '<group name="arm_and_hand"><group name="arm"/><group name="hand"/></group>',
        '<group name="gripper"><chain base_link="tool0" tip_link="left_finger"/></group>',
        EEF,
    )
    assert only(found, "S109") == []


def test_s109_wrist_axis_named_gripper_is_not_a_finger(tmp_path: Path) -> None:
    urdf = ARM_URDF.replace('"joint3"', '"gripper_yaw"')
    (tmp_path / "arm.urdf").write_text(urdf, encoding="utf-8")
    srdf = tmp_path / "arm.srdf"
    srdf.write_text(f'<robot name="arm">\n{ARM}\n</robot>\n', encoding="utf-8")
    assert lint_paths([srdf], LintOptions(urdf=tmp_path / "arm.urdf")).findings == []


# ---- real robots (example-robot-data, skipped when absent) -------------------------------------------

REAL_DEFECTS = {
    # parent_link names the joint 'LeftGripperYaw' instead of its link 'LeftGripperYawLink'
    ("alex_description/srdf/alex_nub_hands.srdf", "alex_description/urdf/alex_nub_hands.urdf"): [
        ("S105", 68),
        ("S105", 69),
    ],
    # leg chains start at 'chest' (above the root); group_state sets an undeclared 'root_joint';
    # the SRDF's robot is 'icub', the URDF's 'iCub' (srdfdom compares them exactly)
    ("icub_description/srdf/icub.srdf", "icub_description/robots/icub.urdf"): [
        ("S101", 86),
        ("S104", 11),
        ("S104", 20),
        ("S110", 2),
    ],
    # arm_up puts j2s6s200_joint_3 at -1.5707, below its lower limit 0.33
    ("kinova_description/srdf/kinova.srdf", "kinova_description/robots/kinova.urdf"): [("S106", 19)],
    # chain base_link 'base' does not exist in z1.urdf; the SRDF's robot is 'z1', the URDF's 'z1_description'
    ("z1_description/srdf/z1.srdf", "z1_description/urdf/z1.urdf"): [("S102", 11), ("S110", 2)],
    ("panda_description/srdf/panda.srdf", "panda_description/urdf/panda.urdf"): [],
    ("pr2_description/srdf/pr2.srdf", "pr2_description/urdf/pr2.urdf"): [],
    ("ur_description/srdf/ur5_gripper.srdf", "ur_description/urdf/ur5_gripper.urdf"): [],
    ("xarm_description/srdf/xarm7.srdf", "xarm_description/urdf/xarm7.urdf"): [],
    ("anymal_c_simple_description/srdf/anymal.srdf", "anymal_c_simple_description/urdf/anymal.urdf"): [],
}


def _erd(relative: str) -> Path:
    hits = glob.glob(f"{sys.prefix}/lib/python*/site-packages/cmeel.prefix/share/example-robot-data/robots/{relative}")
    if not hits:
        pytest.skip(f"example-robot-data not installed ({relative})")
    return Path(hits[0])


@pytest.mark.parametrize("srdf, urdf", list(REAL_DEFECTS), ids=[s.split("/")[-1] for s, _ in REAL_DEFECTS])
def test_real_robot_srdf(srdf: str, urdf: str) -> None:
    found = lint_paths([_erd(srdf)], LintOptions(urdf=_erd(urdf))).findings
    assert sorted(codes(found)) == sorted(REAL_DEFECTS[(srdf, urdf)])


def test_real_robot_hyq_subgroups_suggest_leg_groups() -> None:
    srdf = _erd("hyq_description/srdf/hyq.srdf")
    found = lint_paths([srdf], LintOptions(urdf=_erd("hyq_description/robots/hyq_no_sensors.urdf"))).findings
    s103 = only(found, "S103")
    assert len(s103) == 16 and s103[0].line == 33 and "did you mean 'lf_leg'" in s103[0].message


# ---- S110-S112: what MoveIt and srdfdom do with the pair ---------------------------------------


def test_s110_robot_name_differs_from_the_urdf_given(tmp_path: Path) -> None:
    path = tmp_path / "config" / "arm.srdf"
    path.parent.mkdir()
    path.write_text(f'<robot name="arm_v2">\n{ARM}\n</robot>\n', encoding="utf-8")
    (tmp_path / "arm.urdf").write_text(ARM_URDF, encoding="utf-8")
    (hit,) = [f for f in lint_paths([path], LintOptions(urdf=tmp_path / "arm.urdf")).findings if f.code == "S110"]
    assert hit.line == 1 and "SRDF robot 'arm_v2' is not the URDF's robot 'arm'" in hit.message
    # a URDF armtool picked beside the SRDF may be another variant: no finding
    (tmp_path / "config" / "arm.urdf").write_text(ARM_URDF, encoding="utf-8")
    assert "S110" not in [f.code for f in lint_paths([path], LintOptions()).findings]


def test_s111_virtual_joint_child_is_not_the_root(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        ARM,
        '<virtual_joint name="world_joint" type="fixed" parent_frame="world" child_link="link1"/>',
        '<virtual_joint name="ok" type="fixed" parent_frame="world" child_link="base_link"/>',
    )
    assert [(f.code, f.line) for f in found if f.code == "S111"] == [("S111", 3)]
    assert "root link 'base_link'" in next(f for f in found if f.code == "S111").message


@pytest.mark.parametrize(
    ("child", "kind", "severity"),
    [
        ("link1", "fixed", Severity.ERROR),  # a moving joint carries link1: MoveIt's skip loses the attachment
        ("tool0", "fixed", Severity.ERROR),
        ("mount", "fixed", Severity.INFO),  # fixed to the root: the skip changes nothing (Gazebo's world link)
        ("mount", "floating", Severity.ERROR),  # a floating base MoveIt skips: it never moves
    ],
)
def test_s111_is_graded_by_what_moveit_does(tmp_path: Path, child: str, kind: str, severity: Severity) -> None:
    """Issue 27 item 5: MoveIt skips a virtual joint whose child is not the root; where fixed joints
    attach that child to the root and the virtual joint is fixed, nothing is lost."""
    urdf = ARM_URDF.replace(
        "</robot>",
        f"{LINK.format(name='world')}\n"
        '<joint name="world_to_mount" type="fixed"><parent link="world"/><child link="mount"/></joint>\n'
        f"{LINK.format(name='mount')}\n"
        '<joint name="mount_to_base" type="fixed"><parent link="mount"/><child link="base_link"/></joint>\n</robot>',
    )
    (tmp_path / "arm.urdf").write_text(urdf, encoding="utf-8")
    path = tmp_path / "config" / "arm.srdf"
    path.parent.mkdir()
    path.write_text(
        f'<robot name="arm">\n<virtual_joint name="vj" type="{kind}" parent_frame="odom" child_link="{child}"/>\n</robot>\n'
    )
    (hit,) = [f for f in lint_paths([path], LintOptions(urdf=tmp_path / "arm.urdf")).findings if f.code == "S111"]
    assert (hit.line, hit.severity) == (2, severity)
    assert ("harmless" in hit.message) is (severity is Severity.INFO)


def test_s113_virtual_joint_without_a_name(tmp_path: Path) -> None:
    """srdfdom drops it: "Name of virtual joint is not specified"."""
    found = lint_srdf(
        tmp_path,
        '<virtual_joint type="floating" parent_frame="odom" child_link="base_link"/>',
        '<virtual_joint name="vj" parent_frame="odom" child_link="base_link"/>',
        '<virtual_joint name="ok" type="fixed" parent_frame="world" child_link="base_link"/>',
    )
    hits = [(f.line, f.message.split(" (URDF:")[0]) for f in found if f.code == "S113"]
    assert hits == [
        (2, '<virtual_joint> without name: srdfdom drops it ("Name of virtual joint is not specified")'),
        (3, '<virtual_joint> without type: srdfdom drops it ("Type of virtual joint is not specified")'),
    ]


def test_s112_passive_joint_inside_a_group(tmp_path: Path) -> None:
    found = lint_srdf(
        tmp_path,
        '<group name="arm"><chain base_link="base_link" tip_link="tool0"/>',
        '<passive_joint name="joint3"/></group>',
        '<group name="hand"><joint name="left_finger_joint"/>',
        '<passive_joint name="right_finger_joint"/></group>',
        '<passive_joint name="joint2"/>',
    )
    hits = [(f.line, f.severity) for f in found if f.code == "S112"]
    assert hits == [(3, Severity.WARNING), (5, Severity.INFO)]  # a mimic joint's entry only does nothing
