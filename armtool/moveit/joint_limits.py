"""MoveIt's joint_limits.yaml: per-joint overrides of the URDF's limits, plus acceleration (and jerk)
limits the URDF cannot hold, and the default scaling factors.

MoveIt reads `robot_description_planning.joint_limits.<joint>.<key>` for each joint of its robot
model (moveit_ros_planning's RobotModelLoader::configure): `max_position`/`min_position` (doubles),
`has_velocity_limits`/`has_acceleration_limits`/`has_jerk_limits` (bools), and `max_velocity`,
`max_acceleration`, `max_jerk` (doubles, read only when their flag is true). Keys for joints the
model lacks are never looked at. ros2_control's joint_limits and Pilz add deceleration, effort and
soft limits with the same naming.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from armtool.moveit.params import (
    NameRef,
    Scalar,
    Section,
    as_scalar,
    child,
    is_mapping,
    items,
    key_node,
    moveit_section,
    name_ref,
)

if TYPE_CHECKING:
    import yaml

NAMESPACE = "robot_description_planning"
# The keys and the ROS 2 parameter type their readers declare (MoveIt's RobotModelLoader, Pilz's
# joint limits aggregator, ros2_control's joint_limits).
KEY_TYPES: dict[str, str] = {
    "has_position_limits": "bool",
    "min_position": "double",
    "max_position": "double",
    "has_velocity_limits": "bool",
    "max_velocity": "double",
    "has_acceleration_limits": "bool",
    "max_acceleration": "double",
    "has_deceleration_limits": "bool",
    "max_deceleration": "double",
    "has_jerk_limits": "bool",
    "max_jerk": "double",
    "has_effort_limits": "bool",
    "max_effort": "double",
    "angle_wraparound": "bool",
    "has_soft_limits": "bool",
    "k_position": "double",
    "k_velocity": "double",
    "soft_lower_limit": "double",
    "soft_upper_limit": "double",
}
SCALING_KEYS = ("default_velocity_scaling_factor", "default_acceleration_scaling_factor")
# A limit and the flag that switches it on: MoveIt reads the limit only when the flag is true.
FLAG_OF = {
    "max_velocity": "has_velocity_limits",
    "max_acceleration": "has_acceleration_limits",
    "max_jerk": "has_jerk_limits",
    "max_deceleration": "has_deceleration_limits",
    "max_effort": "has_effort_limits",
}


@dataclass
class JointEntry:
    """One joint's settings as written (`written` may hold launch substitutions)."""

    name: NameRef
    line: int
    column: int
    values: dict[str, Scalar] = field(default_factory=dict)  # scalar settings
    not_scalar: dict[str, tuple[str, int, int]] = field(default_factory=dict)  # key -> (shape, line, column)
    not_a_mapping: str | None = None  # what stands where the settings belong

    def flag(self, key: str) -> bool:
        value = self.values.get(key)
        return bool(value is not None and value.flag())

    def limit(self, key: str) -> float | None:
        """A limit MoveIt applies: the number, when its flag (if it has one) is true."""
        flag = FLAG_OF.get(key)
        if flag is not None and not self.flag(flag):
            return None
        value = self.values.get(key)
        return value.number() if value is not None else None


@dataclass
class JointLimitsFile:
    path: Path
    section: Section
    joint_limits_at: tuple[int, int] | None  # where `joint_limits:` is written
    joints: list[JointEntry]
    scaling: dict[str, Scalar]
    scaling_not_scalar: dict[str, tuple[str, int, int]]

    def entry_for(self, joint: str) -> JointEntry | None:
        """The entry that sets this URDF joint, when one matches."""
        return next((e for e in self.joints if joint in e.name.matches([joint])), None)


def is_moveit_joint_limits(root: yaml.Node | None) -> bool:
    """MoveIt's format: `joint_limits:` (possibly in a ROS 2 parameter file) mapping joints to
    settings with its keys, or the default scaling factors. Franka's `joint1: limit: ...` and
    Kinova's `joint_names: [...]` lists are other tools' files."""
    section = moveit_section(root, NAMESPACE).mapping
    limits = child(section, "joint_limits")
    if limits is not None:
        for _, _, entry in items(limits):
            if any(key in KEY_TYPES for key, _, _ in items(entry)):
                return True
    return any(key_node(section, key) is not None for key in SCALING_KEYS)


def read_joint_limits(path: Path, root: yaml.Node | None, known_args: dict[str, str] | None = None) -> JointLimitsFile:
    """The file's joints and scaling factors (call is_moveit_joint_limits first)."""
    from armtool.moveit.params import position, shape

    section = moveit_section(root, NAMESPACE)
    limits_key = key_node(section.mapping, "joint_limits")
    limits = child(section.mapping, "joint_limits")
    joints: list[JointEntry] = []
    for name, knode, value in items(limits):
        line, column = position(knode)
        entry = JointEntry(name_ref(name, known_args), line, column)
        if not is_mapping(value):
            entry.not_a_mapping = shape(value)
        for key, _, setting in items(value):
            scalar = as_scalar(setting)
            if scalar is None:
                entry.not_scalar[key] = (shape(setting), *position(setting))
            else:
                entry.values[key] = scalar
        joints.append(entry)
    scaling: dict[str, Scalar] = {}
    scaling_bad: dict[str, tuple[str, int, int]] = {}
    for key in SCALING_KEYS:
        node = child(section.mapping, key)
        if node is None:
            continue
        scalar = as_scalar(node)
        if scalar is None:
            scaling_bad[key] = (shape(node), *position(node))
        else:
            scaling[key] = scalar
    return JointLimitsFile(
        path, section, position(limits_key) if limits_key is not None else None, joints, scaling, scaling_bad
    )


def load_joint_limits(path: Path, known_args: dict[str, str] | None = None) -> JointLimitsFile:
    """A joint_limits.yaml for a command (`traj --joint-limits`, `--moveit-config`): any layout;
    an ArmtoolError with file:line when it is not YAML or not MoveIt's format."""
    from armtool.errors import ArmtoolError
    from armtool.moveit.params import load_document

    root = load_document(path, "joint_limits.yaml")
    if not is_moveit_joint_limits(root):
        raise ArmtoolError(
            "not MoveIt's joint_limits.yaml: no `joint_limits:` mapping of joints to limits (flat, or in a ROS 2 "
            "parameter file under NODE: ros__parameters: robot_description_planning:)",
            str(path),
            "MoveIt's format: joint_limits: {joint1: {has_acceleration_limits: true, max_acceleration: 5.0}}",
        )
    return read_joint_limits(path, root, known_args)
