from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import ControllersContext
from armtool.lint.rule import Rule, Target
from armtool.suggest import did_you_mean


class ControllerNotDefined(Rule):
    """
    What it does:
    Reports a controller named in one place and defined nowhere else it must be: a name in
    `controller_names` without its settings (type, action_ns, joints), settings of a controller
    that `controller_names` does not list, and a controller of MoveIt's list that the package's
    ros2_controllers.yaml (ROS 1: ros_controllers.yaml) does not declare under
    `controller_manager`.

    Why is this bad?
    moveit_simple_controller_manager builds a handle only for the listed names, from their
    settings: a listed name without settings has no joints, unlisted settings are ignored. MoveIt
    then sends trajectories to the action `<name>/<action_ns>`, which only a controller of that
    name serves: when the controller manager never loads one, execution waits and fails ("Action
    client not connected to action server").

    Example:
    controller_names: [arm_controller]                  (moveit_controllers.yaml)
    controller_manager: {ros__parameters: {manipulator_controller: {type: ...}}}  (ros2_controllers.yaml)

    Use instead:
    controller_names: [manipulator_controller]
    """

    code, name, severity, target = "C103", "controller-not-defined", Severity.ERROR, Target.CONTROLLERS

    def check(self, ctx: ControllersContext) -> Iterator[Finding]:
        moveit = ctx.moveit
        if moveit is None:
            return
        listed = {s.text: s for s in moveit.listed}
        robot = ctx.robot_controllers()
        simple = moveit.manager is None or "SimpleControllerManager" in moveit.manager.text
        for name, scalar in listed.items():
            if name not in moveit.controllers:
                yield ctx.finding_at_scalar(
                    self,
                    scalar,
                    f"controller '{name}' is listed but has no settings (type, action_ns, joints)",
                    hint=f"add `{name}:` with type, action_ns and joints beside controller_names",
                )
            elif robot is not None and simple and robot.path != ctx.path and name not in robot.declared:
                yield ctx.finding_at_scalar(
                    self,
                    scalar,
                    f"controller '{name}' is not declared in {robot.path.name}"
                    f"{did_you_mean(name, [d for d in robot.declared if d not in listed])}: "
                    "no controller serves its action",
                    hint=f"declare {name} under controller_manager in {robot.path.name}, or rename it here",
                )
        if not moveit.listed:
            return
        for name, controller in moveit.controllers.items():
            if name not in listed and (controller.type is not None or controller.joints is not None):
                yield ctx.finding_at(
                    self,
                    controller.line,
                    controller.column,
                    f"controller '{name}' has settings but controller_names does not list it: MoveIt ignores it",
                    hint=f"add {name} to controller_names, or remove its settings",
                ).with_severity(Severity.WARNING)
