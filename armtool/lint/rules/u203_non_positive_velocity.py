from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


class NonPositiveVelocity(Rule):
    """
    What it does:
    Reports a joint limit with velocity="0" or a negative velocity.

    Why is this bad?
    MoveIt's RobotModel reads a velocity of 0 as "no velocity limit", and its time
    parameterization (TOTG) then refuses the trajectory ("No velocity limit was defined for
    joint ..."): the path is planned and cannot be timed, unless joint_limits.yaml supplies
    a limit.

    Example:
    <limit lower="-1.57" upper="1.57" effort="30" velocity="0"/>

    Use instead:
    <limit lower="-1.57" upper="1.57" effort="30" velocity="2.0"/>
    """

    code, name, severity, target = "U203", "non-positive-velocity", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            limit = joint.limit()
            if limit is None or not joint.moves:
                continue
            value = parse_floats(joint.limits.get("velocity"))
            if value and len(value) == 1 and value[0] <= 0:
                yield ctx.finding(
                    self,
                    limit,
                    f"joint '{joint.name}': velocity limit is {joint.limits.get('velocity')}",
                    attr="velocity",
                    hint='set the joint\'s real maximum speed (rad/s or m/s), e.g. velocity="2.0"',
                )
