from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.joint_limits import FLAG_OF


class LimitWithoutFlag(Rule):
    """
    What it does:
    Reports a `max_velocity`, `max_acceleration`, `max_jerk`, `max_deceleration` or
    `max_effort` in joint_limits.yaml whose `has_*_limits` flag is missing.

    Why is this bad?
    MoveIt reads the value only when the flag is true (RobotModelLoader: `if (has_vel_limits)
    ... max_velocity`); ros2_control's joint_limits does the same. Without the flag the number
    is never read: the joint keeps the URDF's velocity and has no acceleration limit.

    Example:
    joint1:
      max_acceleration: 5.0

    Use instead:
    joint1:
      has_acceleration_limits: true
      max_acceleration: 5.0
    """

    code, name, severity, target = "L108", "limit-without-flag", Severity.WARNING, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        for entry in ctx.doc.joints:
            for key, flag in FLAG_OF.items():
                value = entry.values.get(key)
                if value is None or flag in entry.values or flag in entry.not_scalar:
                    continue
                yield ctx.finding_at_scalar(
                    self,
                    value,
                    f"joint '{entry.name.written}': {key} {value.text} is never read: {flag} is missing",
                    hint=f"add {flag}: true",
                )
