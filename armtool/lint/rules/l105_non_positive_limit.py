from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.joint_limits import FLAG_OF

_POSITIVE = ("max_velocity", "max_acceleration", "max_jerk", "max_effort")


class NonPositiveLimit(Rule):
    """
    What it does:
    Reports a velocity, acceleration, jerk or effort limit in joint_limits.yaml that is zero
    or negative while its `has_*_limits` flag is true, and a `min_position` above the
    `max_position` of the same joint.

    Why is this bad?
    MoveIt takes the value as the bound (RobotModelLoader sets max = value and min = -value):
    a zero velocity or acceleration makes time parameterization refuse the joint ("Invalid
    max_velocity 0 specified for 'joint1', must be greater than 0.0"), a negative one gives
    min above max, and the planner cannot move the joint at all.

    Example:
    joint1:
      has_acceleration_limits: true
      max_acceleration: 0

    Use instead:
    joint1:
      has_acceleration_limits: true
      max_acceleration: 5.0
    """

    code, name, severity, target = "L105", "non-positive-limit", Severity.ERROR, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        for entry in ctx.doc.joints:
            for key in _POSITIVE:
                value = entry.values.get(key)
                number = value.number() if value is not None else None
                if value is None or number is None or number > 0 or not entry.flag(FLAG_OF[key]):
                    continue
                yield ctx.finding_at_scalar(
                    self,
                    value,
                    f"joint '{entry.name.written}': {key} is {value.text} with {FLAG_OF[key]}: true",
                    hint=f"a positive {key}, or {FLAG_OF[key]}: false",
                )
            low, high = entry.values.get("min_position"), entry.values.get("max_position")
            lo, hi = (low.number() if low else None), (high.number() if high else None)
            if low is not None and lo is not None and hi is not None and lo > hi:
                yield ctx.finding_at_scalar(
                    self,
                    low,
                    f"joint '{entry.name.written}': min_position {low.text} is above max_position {high.text if high else ''}",
                    hint="swap them",
                )
