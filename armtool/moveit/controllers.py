"""The controllers of a MoveIt config package, as MoveIt and ros2_control read them.

Two kinds of file, in both ROS generations:

- MoveIt's own list of the controllers it sends trajectories to. ROS 2 (`moveit_controllers.yaml`,
  read by moveit_simple_controller_manager): `moveit_simple_controller_manager: controller_names:
  [...]` and one `<name>: {type, action_ns, joints}` per name; `type` is FollowJointTrajectory,
  GripperCommand or (since moveit2#3246, 2025, on Rolling and Jazzy) ParallelGripperCommand, anything
  else is skipped ("Unknown controller type"). ROS 1
  (`simple_moveit_controllers.yaml`, `controllers.yaml`): `controller_list: [{name, type, joints}]`.
- The controllers the robot runs. ROS 2 (`ros2_controllers.yaml`, read by controller_manager):
  `controller_manager: ros__parameters: <name>: {type: pkg/Class}`, and each controller's own
  parameters under `<name>: ros__parameters:` (`joints: [...]`, or `joint:` for a gripper action
  controller). ROS 1 (`ros_controllers.yaml`): `<name>: {type: pkg/Class, joints: [...]}`.

MoveIt finds a controller's action server by its name; the joints it may send to a controller
are the ones MoveIt's file lists for it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from armtool.moveit.params import (
    Scalar,
    as_scalar,
    child,
    items,
    key_node,
    parameter_nodes,
    position,
    sequence,
    strings,
)

if TYPE_CHECKING:
    import yaml

# The action types moveit_simple_controller_manager builds a handle for: MoveIt 1's (and MoveIt 2's
# up to Humble), and MoveIt 2's since moveit2#3246 (2025, backported to Jazzy): its
# ParallelGripperCommandControllerHandle, for control_msgs/ParallelGripperCommand
# (parallel_gripper_action_controller/GripperActionController).
MOVEIT_TYPES = ("FollowJointTrajectory", "GripperCommand")
MOVEIT2_TYPES = (*MOVEIT_TYPES, "ParallelGripperCommand")
MOVEIT_MANAGERS = (
    "moveit_simple_controller_manager/MoveItSimpleControllerManager",
    "moveit_ros_control_interface/Ros2ControlManager",
    "moveit_ros_control_interface/MoveItControllerManager",
    "moveit_fake_controller_manager/MoveItFakeControllerManager",
)
# Controllers of ros2_controllers (ROS 2) and ros_controllers (ROS 1) that MoveIt configs use.
ROS2_TYPES = (
    "joint_trajectory_controller/JointTrajectoryController",
    "joint_state_broadcaster/JointStateBroadcaster",
    "forward_command_controller/ForwardCommandController",
    "forward_command_controller/MultiInterfaceForwardCommandController",
    "position_controllers/JointGroupPositionController",
    "velocity_controllers/JointGroupVelocityController",
    "effort_controllers/JointGroupEffortController",
    "position_controllers/GripperActionController",
    "effort_controllers/GripperActionController",
    "parallel_gripper_action_controller/GripperActionController",
    "admittance_controller/AdmittanceController",
    "diff_drive_controller/DiffDriveController",
    "tricycle_controller/TricycleController",
    "mecanum_drive_controller/MecanumDriveController",
    "ackermann_steering_controller/AckermannSteeringController",
    "bicycle_steering_controller/BicycleSteeringController",
    "tricycle_steering_controller/TricycleSteeringController",
    "force_torque_sensor_broadcaster/ForceTorqueSensorBroadcaster",
    "imu_sensor_broadcaster/IMUSensorBroadcaster",
    "range_sensor_broadcaster/RangeSensorBroadcaster",
    "pose_broadcaster/PoseBroadcaster",
    "gpio_controllers/GpioCommandController",
    "pid_controller/PidController",
)
ROS1_TYPES = (
    "position_controllers/JointTrajectoryController",
    "velocity_controllers/JointTrajectoryController",
    "effort_controllers/JointTrajectoryController",
    "pos_vel_controllers/JointTrajectoryController",
    "pos_vel_acc_controllers/JointTrajectoryController",
    "joint_state_controller/JointStateController",
    "position_controllers/JointPositionController",
    "velocity_controllers/JointVelocityController",
    "effort_controllers/JointEffortController",
    "effort_controllers/JointPositionController",
    "effort_controllers/JointVelocityController",
    "position_controllers/JointGroupPositionController",
    "velocity_controllers/JointGroupVelocityController",
    "effort_controllers/JointGroupEffortController",
    "effort_controllers/JointGroupPositionController",
    "position_controllers/GripperActionController",
    "effort_controllers/GripperActionController",
    "diff_drive_controller/DiffDriveController",
    "force_torque_sensor_controller/ForceTorqueSensorController",
    "imu_sensor_controller/ImuSensorController",
)
# Controller types that take one joint (`joint:`) rather than a list.
SINGLE_JOINT_TYPES = frozenset(
    {
        "position_controllers/GripperActionController",
        "effort_controllers/GripperActionController",
        "parallel_gripper_action_controller/GripperActionController",
        "position_controllers/JointPositionController",
        "velocity_controllers/JointVelocityController",
        "effort_controllers/JointEffortController",
        "effort_controllers/JointPositionController",
        "effort_controllers/JointVelocityController",
    }
)


@dataclass
class Controller:
    """A controller as one file names it."""

    name: str
    line: int
    column: int
    type: Scalar | None = None
    joints: list[Scalar] | None = None  # None: the file gives no joints for it


@dataclass
class MoveItControllers:
    """MoveIt's list (ROS 2 moveit_simple_controller_manager, or ROS 1 controller_list)."""

    path: Path
    manager: Scalar | None
    listed: list[Scalar]  # ROS 2 controller_names (in ROS 1 every controller_list item is listed)
    listed_at: tuple[int, int]  # where the list is written
    controllers: dict[str, Controller] = field(default_factory=dict)  # names with settings
    ros2: bool = True  # MoveIt 2's layout (controller_names), else MoveIt 1's controller_list

    @property
    def known_types(self) -> tuple[str, ...]:
        """The controller types this generation's moveit_simple_controller_manager builds."""
        return MOVEIT2_TYPES if self.ros2 else MOVEIT_TYPES


@dataclass
class RobotControllers:
    """The controllers the robot's controller manager loads (ros2_controllers / ros_controllers)."""

    path: Path
    ros2_params: bool  # ROS 2's format (controller_manager: ros__parameters:), else ROS 1's flat file
    declared: dict[str, Controller] = field(default_factory=dict)  # name -> type (and joints)


def read_moveit_controllers(path: Path, root: yaml.Node | None) -> MoveItControllers | None:
    """MoveIt's controller list, or None when the file holds none."""
    nodes = parameter_nodes(root)
    doc = root
    if nodes is not None:  # moveit_controllers.yaml written as a ROS 2 parameter file
        doc = next((p for p in nodes.values() if child(p, "moveit_simple_controller_manager") is not None), None)
        if doc is None:
            return None
    manager = as_scalar(child(doc, "moveit_controller_manager"))
    simple = child(doc, "moveit_simple_controller_manager")
    if simple is not None:
        names_node = child(simple, "controller_names")
        listed = strings(names_node) or []
        where = key_node(simple, "controller_names") or key_node(doc, "moveit_simple_controller_manager")
        out = MoveItControllers(path, manager, listed, position(where) if where is not None else (1, 1))
        for name, knode, value in items(simple):
            if name == "controller_names":
                continue
            line, column = position(knode)
            out.controllers[name] = Controller(
                name, line, column, as_scalar(child(value, "type")), strings(child(value, "joints"))
            )
        return out
    controller_list = child(doc, "controller_list")
    entries = sequence(controller_list)
    if entries is None:
        return None
    where = key_node(doc, "controller_list")
    out = MoveItControllers(path, manager, [], position(where) if where is not None else (1, 1), ros2=False)
    for entry in entries:
        named = as_scalar(child(entry, "name"))
        if named is None:
            continue
        out.listed.append(named)
        out.controllers[named.text] = Controller(
            named.text, named.line, named.column, as_scalar(child(entry, "type")), strings(child(entry, "joints"))
        )
    return out


def read_robot_controllers(path: Path, root: yaml.Node | None) -> RobotControllers | None:
    """The controllers a controller manager loads, or None when the file declares none."""
    nodes = parameter_nodes(root)
    if nodes is not None:
        manager = next((p for name, p in nodes.items() if name.rsplit("/", 1)[-1] == "controller_manager"), None)
        if manager is None:
            return None
        out = RobotControllers(path, True)
        for name, knode, value in items(manager):
            ctype = as_scalar(child(value, "type"))
            if ctype is None:
                continue  # update_rate and other settings of the manager itself
            line, column = position(knode)
            own = nodes.get(name) or nodes.get(f"/{name}")
            out.declared[name] = Controller(name, line, column, ctype, _joints_of(own, ctype.text))
        return out if out.declared else None
    out = RobotControllers(path, False)
    for name, knode, value in items(root):
        ctype = as_scalar(child(value, "type"))
        if ctype is None or "/" not in ctype.text:
            continue
        line, column = position(knode)
        out.declared[name] = Controller(name, line, column, ctype, _joints_of(value, ctype.text))
    return out if out.declared else None


def _joints_of(params: yaml.Node | None, ctype: str) -> list[Scalar] | None:
    joints = strings(child(params, "joints"))
    if joints is not None:
        return joints
    if ctype in SINGLE_JOINT_TYPES:
        single = as_scalar(child(params, "joint"))
        if single is not None:
            return [single]
    return None
