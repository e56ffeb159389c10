from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import ControllersContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.controllers import ROS1_TYPES, ROS2_TYPES
from armtool.suggest import nearest_within, optimal_string_alignment

# What a ROS 1 controller type is called in ros2_controllers.
ROS2_EQUIVALENT = {
    "position_controllers/JointTrajectoryController": "joint_trajectory_controller/JointTrajectoryController",
    "velocity_controllers/JointTrajectoryController": "joint_trajectory_controller/JointTrajectoryController",
    "effort_controllers/JointTrajectoryController": "joint_trajectory_controller/JointTrajectoryController",
    "pos_vel_controllers/JointTrajectoryController": "joint_trajectory_controller/JointTrajectoryController",
    "pos_vel_acc_controllers/JointTrajectoryController": "joint_trajectory_controller/JointTrajectoryController",
    "joint_state_controller/JointStateController": "joint_state_broadcaster/JointStateBroadcaster",
    "position_controllers/JointPositionController": "position_controllers/JointGroupPositionController",
    "velocity_controllers/JointVelocityController": "velocity_controllers/JointGroupVelocityController",
    "effort_controllers/JointEffortController": "effort_controllers/JointGroupEffortController",
}
# Edits (insertion, deletion, substitution, swap of neighbours) that make a misspelling; another
# real controller (`position_controllers/PilzJointTrajectoryController`) is many more.
TYPO = 2


class UnknownControllerType(Rule):
    """
    What it does:
    Reports a controller type that is one or two letters off a known one: in MoveIt's list
    (FollowJointTrajectory and GripperCommand; in MoveIt 2's `controller_names` layout also
    ParallelGripperCommand, which moveit_simple_controller_manager builds since moveit2#3246, 2025,
    on Rolling and Jazzy; MoveIt 1's `controller_list` has no such handle), and in ros2_controllers.yaml /
    ros_controllers.yaml (the controllers of ros2_controllers / ros_controllers; a ROS 1 type in
    a ROS 2 parameter file is named with its ROS 2 counterpart). A flat file of controllers is
    ROS 1's format (ROS 2's controller manager reads `controller_manager: ros__parameters:` only)
    and is checked against ROS 1's types. Types of other packages that are not close to a known
    one (`picknik_twist_controller/PicknikTwistController`) and launch substitutions
    (`$(arg execution_type)`) pass.

    Why is this bad?
    moveit_simple_controller_manager skips a controller of another type ("Unknown controller
    type"), so MoveIt has no controller for those joints. The controller manager cannot load a
    plugin under a misspelt name ("Loader for controller ... not found"), and the controller
    never starts.

    Example:
    arm_controller:
      type: joint_trajectory_controller/JointTrajectroyController

    Use instead:
    arm_controller:
      type: joint_trajectory_controller/JointTrajectoryController
    """

    code, name, severity, target = "C104", "unknown-controller-type", Severity.ERROR, Target.CONTROLLERS

    def check(self, ctx: ControllersContext) -> Iterator[Finding]:
        if ctx.moveit is not None:
            known_types = ctx.moveit.known_types
            for controller in ctx.moveit.controllers.values():
                ctype = controller.type
                if ctype is None or ctype.text in known_types or "$(" in ctype.text:
                    continue  # a launch substitution (roslaunch subst_value) is filled in at launch
                import difflib  # on use, as armtool.suggest: most files have no unknown type

                match = difflib.get_close_matches(ctype.text, known_types, n=1, cutoff=0.5)
                yield ctx.finding_at_scalar(
                    self,
                    ctype,
                    f"controller '{controller.name}': type '{ctype.text}' is not one MoveIt knows; it skips the controller"
                    + (f" (did you mean '{match[0]}'?)" if match else ""),
                    hint="FollowJointTrajectory (an arm) or GripperCommand (a gripper)"
                    + (", or ParallelGripperCommand (MoveIt 2 on Jazzy and later)" if ctx.moveit.ros2 else ""),
                )
        if ctx.robot is None:
            return
        # Only ROS 2's controller manager reads `controller_manager: ros__parameters:`; a flat file of
        # controllers is ROS 1's ros_controllers format, whatever package holds it.
        ros2 = ctx.robot.ros2_params
        known: tuple[str, ...] = ROS2_TYPES if ros2 else ROS1_TYPES
        for controller in ctx.robot.declared.values():
            ctype = controller.type
            if ctype is None or ctype.text in known or "$(" in ctype.text:
                continue
            if ros2 and ctype.text in ROS2_EQUIVALENT:
                yield ctx.finding_at_scalar(
                    self,
                    ctype,
                    f"controller '{controller.name}': '{ctype.text}' is a ROS 1 controller type; ros2_controllers "
                    f"calls it '{ROS2_EQUIVALENT[ctype.text]}'",
                    hint=f"type: {ROS2_EQUIVALENT[ctype.text]}",
                )
                continue
            nearest = nearest_within(ctype.text, known, TYPO, optimal_string_alignment)
            if nearest is not None:
                yield ctx.finding_at_scalar(
                    self,
                    ctype,
                    f"controller '{controller.name}': no controller type '{ctype.text}' (did you mean '{nearest}'?)",
                    hint=f"type: {nearest}",
                )
