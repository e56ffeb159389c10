from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import ControllersContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.params import name_ref
from armtool.suggest import closest


class ControllerUnknownJoint(Rule):
    """
    What it does:
    Reports a joint of a controller that the URDF does not have: in MoveIt's controller list
    (moveit_controllers.yaml, simple_moveit_controllers.yaml) and in the controller manager's
    file (ros2_controllers.yaml `joints`, a gripper action controller's `joint`; ROS 1's
    ros_controllers.yaml). Checked inside a MoveIt config package, against the URDF its SRDF
    describes.

    Why is this bad?
    MoveIt picks the controllers whose joints cover a trajectory's joints: a misspelt joint
    leaves the real one without a controller ("Unable to identify any set of controllers that
    can actuate the specified joints"). ros2_control's joint_trajectory_controller fails to
    configure on a joint no hardware interface provides.

    Example:
    arm_controller:
      joints: [shoulder_pan, shoulder_lift_joint]   # the URDF has shoulder_pan_joint

    Use instead:
    arm_controller:
      joints: [shoulder_pan_joint, shoulder_lift_joint]
    """

    code, name, severity, target = "C101", "controller-unknown-joint", Severity.ERROR, Target.CONTROLLERS

    def check(self, ctx: ControllersContext) -> Iterator[Finding]:
        if ctx.urdf is None:
            return
        known = ctx.urdf.joint_names
        controllers = [
            *(ctx.moveit.controllers.values() if ctx.moveit else ()),
            *(ctx.robot.declared.values() if ctx.robot else ()),
        ]
        for controller in controllers:
            for joint in controller.joints or ():
                ref = name_ref(joint.text, ctx.known_args)
                if ref.matches(known):
                    continue
                match = closest(ref.bare, known)
                yield ctx.finding_at_scalar(
                    self,
                    joint,
                    f"controller '{controller.name}': joint '{joint.text}' is not in the URDF{ctx.urdf_note()}"
                    + (f" (did you mean '{match}'?)" if match else ""),
                    hint=f"rename it to '{match}'" if match else "joints: " + ", ".join(sorted(known)[:20]),
                )
