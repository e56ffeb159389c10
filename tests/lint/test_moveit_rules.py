"""Rules for a MoveIt config package's YAML files (L joint_limits.yaml, P Pilz limits, C controllers):
the bundled clean package lints clean; each rule fires on one edit of a copy of it, at the line."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.finding import Finding, Severity
from armtool.lint.fix import fixed_texts, safe_edits

ROBOTS = Path(__file__).resolve().parents[2] / "fixtures" / "robots"
CLEAN = ROBOTS / "clean_arm_moveit_config"


@pytest.fixture
def package(tmp_path: Path) -> Path:
    """A copy of the clean MoveIt 2 package and of the description it names."""
    shutil.copytree(ROBOTS / "clean_arm", tmp_path / "clean_arm")
    shutil.copytree(CLEAN, tmp_path / "clean_arm_moveit_config")
    return tmp_path / "clean_arm_moveit_config"


def lint(path: Path, **options: object) -> list[Finding]:
    return lint_paths([path], LintOptions(**options)).findings  # type: ignore[arg-type]


def edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text, old
    path.write_text(text.replace(old, new, 1))


def found(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code]


def test_clean_package_lints_clean() -> None:
    assert lint(CLEAN) == []
    assert lint_paths([], LintOptions(moveit_config=CLEAN)).findings == []


# ---- joint_limits.yaml ------------------------------------------------------------------


def test_l101_unknown_joint_with_did_you_mean(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "$(var tf_prefix)joint3:", "$(var tf_prefix)joint_3:")
    (hit,) = found(lint(path), "L101")
    assert hit.line == 11 and "did you mean 'joint3'" in hit.message and "matched by the rest" in hit.message


def test_l101_substitution_known_from_the_xacro_arguments(package: Path) -> None:
    """With tf_prefix known, `$(var tf_prefix)joint1` is `left_joint1`, which this URDF lacks."""
    path = package / "config" / "joint_limits.yaml"
    hits = found(lint(path, xacro_args={"tf_prefix": "left_"}), "L101")
    assert len(hits) == 7


def test_l102_integer_in_a_ros2_package_with_a_safe_fix(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "max_velocity: 2.5,", "max_velocity: 2,")
    edit(path, "default_velocity_scaling_factor: 0.5", "default_velocity_scaling_factor: 1")
    hits = found(lint(path), "L102")
    assert [(h.line, h.severity) for h in hits] == [(6, Severity.ERROR), (11, Severity.ERROR)]
    assert "expected [double] got [integer]" in hits[1].message
    changes = fixed_texts(safe_edits(hits))
    new = changes[path][1]
    assert "max_velocity: 2.0," in new and "default_velocity_scaling_factor: 1.0" in new
    path.write_text(new)
    assert found(lint(path), "L102") == []


def test_l102_not_in_a_ros1_package(package: Path) -> None:
    """roscpp reads an integer parameter as a double: MoveIt 1 takes `max_velocity: 2`."""
    edit(package / "package.xml", "ament_cmake</buildtool_depend>", "catkin</buildtool_depend>")
    edit(package / "package.xml", "<build_type>ament_cmake</build_type>", "")
    path = package / "config" / "joint_limits.yaml"
    path.write_text("joint_limits:\n  joint1: {has_velocity_limits: true, max_velocity: 2}\n")
    assert found(lint(path), "L102") == []


def test_l103_wrong_types(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "{has_velocity_limits: true, max_velocity: 2.0, has_acceleration_limits: true, max_acceleration: 4.0}",
         "{has_velocity_limits: 1, max_velocity: \"2.0\", has_acceleration_limits: true, max_acceleration: [4.0]}")  # fmt: skip
    messages = [h.message for h in found(lint(path), "L103")]
    assert len(messages) == 3
    assert "has_velocity_limits is '1', not a true/false flag" in messages[0]
    assert "max_velocity is the string '2.0', not a number" in messages[1]
    assert "max_acceleration is a list, not a number" in messages[2]


def test_l104_missing_acceleration_for_planning_group_joints(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "max_velocity: 2.0, has_acceleration_limits: true, max_acceleration: 4.0}",
         "max_velocity: 2.0, has_acceleration_limits: false, max_acceleration: 0}")  # fmt: skip
    text = path.read_text()
    path.write_text("\n".join(line for line in text.splitlines() if "joint6:" not in line) + "\n")
    hits = found(lint(path), "L104")
    assert [h.message.split(":")[0] for h in hits] == ["joint 'joint6' (group arm) has no entry"] + [
        "joint '$(var tf_prefix)joint1' (group arm)"
    ]
    assert hits[1].line == 9 and "has_acceleration_limits is false" in hits[1].message
    # a mimic joint (right_finger_joint) is never reported: MoveIt does not time it on its own


def test_l105_non_positive_and_l108_limit_without_flag(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "max_velocity: 2.5, has_acceleration_limits: true, max_acceleration: 5.0}",
         "max_velocity: 2.5, has_acceleration_limits: true, max_acceleration: 0.0}")  # fmt: skip
    edit(path, "{has_velocity_limits: true, max_velocity: 3.5,", "{max_velocity: 3.5,")
    findings = lint(path)
    (zero,) = found(findings, "L105")
    assert zero.line == 11 and "max_acceleration is 0.0 with has_acceleration_limits: true" in zero.message
    (unread,) = found(findings, "L108")
    assert unread.line == 14 and "never read: has_velocity_limits is missing" in unread.message


def test_l106_limit_above_the_urdf(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "$(var tf_prefix)joint2: {has_velocity_limits: true, max_velocity: 2.0,",
         "$(var tf_prefix)joint2: {has_velocity_limits: true, max_velocity: 3.0, max_position: 2.5,")  # fmt: skip
    hits = found(lint(path), "L106")
    assert [h.message.split(" is beyond")[0] for h in hits] == [
        "joint '$(var tf_prefix)joint2': max_velocity 3.0",
        "joint '$(var tf_prefix)joint2': max_position 2.5",
    ]
    assert 'velocity="2.0"' in hits[0].message and hits[0].severity is Severity.WARNING


def test_l106_hint_says_at_least_for_a_lower_bound(tmp_path: Path) -> None:
    """A min_position below the URDF's lower is fixed by raising it: the hint says 'at least', not 'at most'."""
    path = tmp_path / "limits.yaml"
    path.write_text("joint_limits:\n  joint2: {has_position_limits: true, min_position: -2.5, max_position: 2.5}\n")
    low, high = found(lint(path, urdf=ROBOTS / "clean_arm" / "urdf" / "clean_arm.urdf"), "L106")
    assert low.message.startswith("joint 'joint2': min_position -2.5")
    assert "at least the URDF's -2" in (low.hint or "") and "at most the URDF's 2" in (high.hint or "")


LIMITS_ONLY = "joint_limits:\n  joint2: {has_velocity_limits: true, max_velocity: 3.0}\n"


def test_l106_a_limits_file_without_srdf_is_compared_with_the_given_urdf(tmp_path: Path) -> None:
    """Issue 27 item 2: `lint limits.yaml --urdf robot.urdf` compares it even with no SRDF around."""
    path = tmp_path / "limits.yaml"
    path.write_text(LIMITS_ONLY)
    assert found(lint(path), "L106") == []
    (hit,) = found(lint(path, urdf=ROBOTS / "clean_arm" / "urdf" / "clean_arm.urdf"), "L106")
    assert (hit.line, hit.message.split(" is beyond")[0]) == (2, "joint 'joint2': max_velocity 3.0")


def test_l106_a_description_package_limits_file_is_compared_with_its_robot(tmp_path: Path) -> None:
    """khi_duaro_description: config/duaro_joint_limits.yaml beside urdf/duaro.urdf.xacro, no SRDF."""
    shutil.copytree(ROBOTS / "clean_arm", tmp_path / "clean_arm")
    config = tmp_path / "clean_arm" / "config"
    for name in ("clean_arm.srdf", "kinematics.yaml"):
        (config / name).unlink()
    (config / "joint_limits.yaml").write_text(LIMITS_ONLY)
    hits = found(lint(tmp_path / "clean_arm"), "L106")
    assert [(Path(h.path).name, h.line) for h in hits] == [("joint_limits.yaml", 2)]


@pytest.mark.parametrize(
    ("written", "reported"),
    [
        ("5.23599", False),  # radians(300) = 5.2359878 at the 5 decimals written
        ("5.236", False),
        ("5.2360", False),  # 5.2360 ± 0.00005 holds 5.2359878
        ("5.23600", True),  # 5.23600 ± 0.000005 does not
        ("6.283", True),  # 20 % above
        ("10.4717", True),
        ("6", True),  # a whole number shows no precision
    ],
)
def test_l106_tolerance_is_the_precision_written(tmp_path: Path, written: str, reported: bool) -> None:
    """Issue 27 item 3: half a unit in the last digit written, not a percentage."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(
        (ROBOTS / "clean_arm" / "urdf" / "clean_arm.urdf")
        .read_text()
        .replace('velocity="2.0"', 'velocity="5.235987756"', 1)
    )
    limits = tmp_path / "limits.yaml"
    limits.write_text(f"joint_limits:\n  joint1: {{has_velocity_limits: true, max_velocity: {written}}}\n")
    assert bool(found(lint(limits, urdf=urdf), "L106")) is reported


def test_l107_scaling_factor(package: Path) -> None:
    path = package / "config" / "joint_limits.yaml"
    edit(path, "default_acceleration_scaling_factor: 0.25", "default_acceleration_scaling_factor: 25.0")
    (hit,) = found(lint(path), "L107")
    assert hit.line == 7 and "outside (0, 1]" in hit.message


def test_not_moveit_joint_limits_files_are_left_alone(tmp_path: Path) -> None:
    franka = tmp_path / "joint_limits.yaml"
    franka.write_text("joint1:\n  limit:\n    lower: -2\n    upper: 2\n    velocity: 2\n")
    kinova = tmp_path / "arm_joint_limits.yaml"
    kinova.write_text("joint_names:\n  - $(arg prefix)joint_1\nmaximum_velocities:\n  - 1\n")
    assert lint(tmp_path) == []


def test_invalid_yaml_is_l001(tmp_path: Path) -> None:
    path = tmp_path / "joint_limits.yaml"
    path.write_text("joint_limits:\n  j1: {max_velocity: 1.0\n")
    (hit,) = lint(path)
    assert hit.code == "L001" and hit.line == 3


# ---- pilz_cartesian_limits.yaml ---------------------------------------------------------


def test_p101_p102_p103(package: Path) -> None:
    path = package / "config" / "pilz_cartesian_limits.yaml"
    path.write_text(
        "cartesian_limits:\n  max_trans_vel: 1\n  max_trans_acc: 0.0\n  max_trans_dec: 5.0\n  max_rot_velocity: 1.57\n"
    )
    findings = lint(path)
    (missing,) = found(findings, "P101")
    assert "no max_rot_vel" in missing.message and "did you mean 'max_rot_velocity'" in missing.message
    assert [(f.line, f.message.split(":")[0]) for f in found(findings, "P102")] == [
        (3, "max_trans_acc is 0.0"),
        (4, "max_trans_dec is 5.0"),
    ]
    (integer,) = found(findings, "P103")
    assert integer.line == 2 and fixed_texts(safe_edits([integer]))[path][1].startswith(
        "cartesian_limits:\n  max_trans_vel: 1.0\n"
    )


def test_p102_one_aliased_value_gives_its_findings_in_key_order(package: Path) -> None:
    """One node, two keys: the velocity's finding, then the deceleration's (output order of ties)."""
    path = package / "config" / "pilz_cartesian_limits.yaml"
    path.write_text(
        "cartesian_limits:\n  max_trans_vel: 1.0\n  max_trans_acc: 2.25\n  max_rot_vel: &zero 0.0\n"
        "  max_trans_dec: *zero\n"
    )
    assert [(f.line, f.column, f.message.split(":")[0]) for f in found(lint(path), "P102")] == [
        (4, 16, "max_rot_vel is 0.0"),
        (4, 16, "max_trans_dec is 0.0"),
    ]


# ---- controllers ------------------------------------------------------------------------


def test_c101_controller_joint_not_in_the_urdf(package: Path) -> None:
    edit(package / "config" / "moveit_controllers.yaml", "      - joint4", "      - joint_4")
    edit(package / "config" / "ros2_controllers.yaml", "joint: left_finger_joint", "joint: left_fingr_joint")
    findings = lint(package / "config")
    assert [(f.path.rsplit("/", 1)[1], f.line) for f in found(findings, "C101")] == [
        ("moveit_controllers.yaml", 17),
        ("ros2_controllers.yaml", 32),
    ]
    assert "did you mean 'left_finger_joint'" in found(findings, "C101")[1].message


def test_c102_group_without_controller(package: Path) -> None:
    path = package / "config" / "moveit_controllers.yaml"
    edit(path, "    - gripper_controller\n", "")
    findings = lint(package / "config")
    (hit,) = found(findings, "C102")
    assert hit.path.endswith("moveit_controllers.yaml") and hit.line == 5
    assert "planning group 'gripper'" in hit.message and "left_finger_joint" in hit.message
    # another controllers file of the package that covers the group is enough (the launch may load it)
    (package / "config" / "gripper_moveit_controllers.yaml").write_text(
        path.read_text().replace("    - arm_controller\n", "    - arm_controller\n    - gripper_controller\n")
    )
    assert found(lint(package / "config"), "C102") == []


def test_c103_controller_named_but_not_defined(package: Path) -> None:
    edit(
        package / "config" / "ros2_controllers.yaml",
        "    gripper_controller:\n      type:",
        "    hand_controller:\n      type:",
    )
    edit(
        package / "config" / "moveit_controllers.yaml",
        "    - arm_controller\n",
        "    - arm_controller\n    - wrist_controller\n",
    )
    findings = found(lint(package / "config" / "moveit_controllers.yaml"), "C103")
    assert [f.message.split(":")[0] for f in findings] == [
        "controller 'wrist_controller' is listed but has no settings (type, action_ns, joints)",
        "controller 'gripper_controller' is not declared in ros2_controllers.yaml (did you mean 'hand_controller'?)",
    ]


def test_c104_misspelt_types(package: Path) -> None:
    edit(package / "config" / "moveit_controllers.yaml", "type: GripperCommand", "type: GripperComand")
    edit(package / "config" / "ros2_controllers.yaml", "joint_trajectory_controller/JointTrajectoryController",
         "joint_trajectory_controller/JointTrajectroyController")  # fmt: skip
    edit(package / "config" / "ros2_controllers.yaml", "joint_state_broadcaster/JointStateBroadcaster",
         "joint_state_controller/JointStateController")  # fmt: skip
    hits = found(lint(package / "config"), "C104")
    assert [h.message.split(" (")[0].split(";")[0] for h in hits] == [
        "controller 'gripper_controller': type 'GripperComand' is not one MoveIt knows",
        "controller 'arm_controller': no controller type 'joint_trajectory_controller/JointTrajectroyController'",
        "controller 'joint_state_broadcaster': 'joint_state_controller/JointStateController' is a ROS 1 controller type",
    ]


def test_c104_parallel_gripper_command_is_moveit_2s_and_not_moveit_1s(package: Path) -> None:
    """moveit2#3246 (Jazzy, Rolling) added ParallelGripperCommand to moveit_simple_controller_manager:
    it drives its joints (no C102, no C104); MoveIt 1's controller_list has no such handle."""
    edit(package / "config" / "moveit_controllers.yaml", "type: GripperCommand", "type: ParallelGripperCommand")
    findings = lint(package / "config")
    assert found(findings, "C104") == [] and found(findings, "C102") == []
    ros1 = package / "config" / "simple_moveit_controllers.yaml"
    ros1.write_text(
        "controller_list:\n  - name: gripper_controller\n    action_ns: gripper_cmd\n"
        "    type: ParallelGripperCommand\n    joints: [left_finger_joint]\n"
    )
    (hit,) = found(lint(ros1), "C104")
    assert (hit.line, hit.message.split(";")[0]) == (
        4,
        "controller 'gripper_controller': type 'ParallelGripperCommand' is not one MoveIt knows",
    )


def test_c104_leaves_other_real_controllers_and_substitutions_alone(tmp_path: Path) -> None:
    path = tmp_path / "ros_controllers.yaml"
    path.write_text(
        "arm:\n  type: position_controllers/PilzJointTrajectoryController\n  joints: [a]\n"
        "fake:\n  type: $(arg execution_type)\n  joints: [a]\n"
    )
    assert lint(path) == []


def test_ros1_package_controller_list_and_ros_controllers(package: Path) -> None:
    """MoveIt 1: simple_moveit_controllers.yaml's controller_list against ros_controllers.yaml."""
    edit(package / "package.xml", "ament_cmake</buildtool_depend>", "catkin</buildtool_depend>")
    edit(package / "package.xml", "<build_type>ament_cmake</build_type>", "")
    config = package / "config"
    for name in ("moveit_controllers.yaml", "ros2_controllers.yaml"):
        (config / name).unlink()
    (config / "simple_moveit_controllers.yaml").write_text(
        "controller_list:\n"
        "  - name: arm_controller\n    action_ns: follow_joint_trajectory\n    type: FollowJointTrajectory\n"
        "    joints: [joint1, joint2, joint3, joint4, joint5, joint6]\n"
        "  - name: gripper_controller\n    action_ns: gripper_cmd\n    type: GripperCommand\n    joints: [left_finger_joint]\n"
    )
    (config / "ros_controllers.yaml").write_text(
        "arm_controller:\n  type: position_controllers/JointTrajectoryController\n"
        "  joints: [joint1, joint2, joint3, joint4, joint5, joint6]\n"
        "hand_controller:\n  type: position_controllers/GripperActionController\n  joint: left_finger_joint\n"
    )
    findings = lint(config)
    assert [(f.code, f.line) for f in findings] == [("C103", 6)]
    assert "'gripper_controller' is not declared in ros_controllers.yaml" in findings[0].message


@pytest.mark.parametrize("name", ["moveit_controllers.yaml", "simple_moveit_controllers.yaml"])
def test_c103_settings_controller_names_does_not_list_whatever_the_file_name(package: Path, name: str) -> None:
    """moveit_simple_controller_manager ignores settings of a controller controller_names does not
    list; the file's format says so, not its name (a ROS 1 controller_list lists every controller)."""
    path = package / "config" / name
    text = (package / "config" / "moveit_controllers.yaml").read_text()
    path.write_text(text.replace("    - gripper_controller\n", "", 1))
    findings = found(lint(path), "C103")
    assert [(f.line, f.severity, f.message) for f in findings] == [
        (
            19,  # gripper_controller: in the file, less the line that listed it
            Severity.WARNING,
            "controller 'gripper_controller' has settings but controller_names does not list it: MoveIt ignores it",
        )
    ]
