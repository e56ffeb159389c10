from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import ControllersContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.params import name_ref


class GroupWithoutController(Rule):
    """
    What it does:
    Reports a planning group (SRDF) whose moving joints (revolute, prismatic, continuous; not
    mimic, not passive) are not all driven by the controllers of any one MoveIt controllers file
    of the package. Reported once, in the file MoveIt's launch loads for trajectory execution
    (MoveItConfigsBuilder: the only `config/*_controllers.yaml`, or `moveit_controllers.yaml`).
    Which file a launch passes can differ (the Panda's demo loads gripper_moveit_controllers.yaml
    for its hand), so a group any file covers passes. With MoveIt's Ros2ControlManager the
    controllers come from ros2_controllers.yaml.

    Why is this bad?
    Planning works, but executing a plan of that group fails: MoveIt's trajectory execution
    manager finds no set of controllers for its joints ("Unable to identify any set of
    controllers that can actuate the specified joints").

    Example:
    <group name="gripper"><joint name="finger_joint"/></group>      (SRDF)
    controller_names: [arm_controller]                               (moveit_controllers.yaml)

    Use instead:
    controller_names: [arm_controller, gripper_controller]
    gripper_controller: {type: GripperCommand, action_ns: gripper_cmd, joints: [finger_joint]}
    """

    code, name, severity, target = "C102", "group-without-controller", Severity.WARNING, Target.CONTROLLERS

    def check(self, ctx: ControllersContext) -> Iterator[Finding]:
        package = ctx.package
        if package is None or ctx.moveit is None or ctx.urdf is None:
            return
        owner = package.package.moveit_controllers
        if owner not in package.moveit:
            owner = min(package.moveit) if package.moveit else None
        if owner != ctx.path:
            return  # reported once, in the file trajectory execution loads
        covers: list[set[str]] = []
        uses_ros2_control = False
        for moveit in package.moveit.values():
            listed = {s.text for s in moveit.listed}
            covers.append(
                {
                    name_ref(j.text, ctx.known_args).bare
                    for name, c in moveit.controllers.items()
                    if name in listed and (c.type is None or c.type.text in moveit.known_types)
                    for j in (c.joints or ())
                }
            )
            uses_ros2_control |= moveit.manager is not None and "Ros2ControlManager" in moveit.manager.text
        robot = ctx.robot_controllers()
        if uses_ros2_control and robot is not None:
            covers.append({j.text for c in robot.declared.values() for j in (c.joints or ())})
        mine = covers[list(package.moveit).index(ctx.path)]  # ctx.path is the owner, one of package.moveit
        line, column = ctx.moveit.listed_at
        for group, joints in ctx.active_group_joints().items():
            if not joints or any(set(joints) <= cover for cover in covers):
                continue
            missing = [j for j in joints if j not in mine]
            yield ctx.finding_at(
                self,
                line,
                column,
                f"planning group '{group}': no controller here drives {', '.join(missing)}, nor does any other "
                "controllers file of the package: executing its plans fails",
                hint="add a controller for these joints to controller_names (with type, action_ns and joints)",
            )
