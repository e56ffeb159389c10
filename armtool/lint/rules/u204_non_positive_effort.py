from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


class NonPositiveEffort(Rule):
    """
    What it does:
    Reports a joint limit with effort="0" or a negative effort. When every moving joint has
    effort="0" (ROS-Industrial's convention for a kinematics-only model), or the model has no
    <inertial> at all (so effort="0" is a placeholder beside real efforts, like the missing
    inertials), the model is reported once, at info level, not joint by joint. effort="0" on a
    passive joint is true, not a defect: a continuous joint that none of the model's
    transmissions, ros2_control blocks or Gazebo plugins names (a caster's swivel and wheel;
    armtool.lint.actuation). A negative effort is always reported.

    Why is this bad?
    Controllers and simulators clamp the commanded torque or force to the effort limit:
    with 0 the joint cannot move in Gazebo or under ros2_control effort interfaces.

    Example:
    <limit lower="0" upper="0.04" effort="0" velocity="0.2"/>

    Use instead:
    <limit lower="0" upper="0.04" effort="20" velocity="0.2"/>
    """

    code, name, severity, target = "U204", "non-positive-effort", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        from armtool.lint import kinematics_only
        from armtool.lint.actuation import driven_joints, is_passive

        placeholders = kinematics_only.efforts_are_placeholders(ctx)
        driven = driven_joints(ctx)
        if placeholders and not kinematics_only.has_no_inertials(ctx):  # else U401's one finding says it
            yield ctx.finding(self, ctx.root, kinematics_only.description(ctx)).with_severity(Severity.INFO)
        for joint in ctx.joints:
            limit = joint.limit()
            if limit is None or not joint.moves:
                continue
            value = parse_floats(joint.limits.get("effort"))
            if not value or len(value) != 1 or value[0] > 0:
                continue
            if value[0] < 0 or not (placeholders or is_passive(joint, driven)):
                yield ctx.finding(
                    self,
                    limit,
                    f"joint '{joint.name}': effort limit is {joint.limits.get('effort')}",
                    attr="effort",
                    hint='set the actuator\'s rated torque (N·m) or force (N), e.g. effort="30"',
                )
