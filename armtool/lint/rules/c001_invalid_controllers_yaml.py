from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class InvalidControllersYaml(Rule):
    """
    What it does:
    Reports a controllers file (moveit_controllers.yaml, ros2_controllers.yaml, ROS 1's
    ros_controllers.yaml and simple_moveit_controllers.yaml) that is not valid YAML. Reported by
    the loader.

    Why is this bad?
    The launch that loads it stops: MoveIt gets no controllers, or the controller manager none.

    Example:
    controller_manager:
      ros__parameters:
       update_rate: 100
        arm_controller:

    Use instead:
    controller_manager:
      ros__parameters:
        update_rate: 100
        arm_controller:
          type: joint_trajectory_controller/JointTrajectoryController
    """

    code, name, severity, target = "C001", "invalid-controllers-yaml", Severity.ERROR, Target.CONTROLLERS

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
