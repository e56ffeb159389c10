from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import PilzContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.params import as_scalar, child, position, shape

# Checked before max_trans_dec: two findings on one aliased value (`max_trans_dec: *v`) keep this order.
POSITIVE = tuple(key for key in PilzContext.KEYS if key != "max_trans_dec")


class InvalidCartesianLimit(Rule):
    """
    What it does:
    Reports a Pilz Cartesian limit that is not a number, a velocity or acceleration that is
    zero or negative, and a `max_trans_dec` that is zero or positive (a deceleration is
    negative: "Maximum translational deceleration, always <=0 [m/s^2]", Pilz's CartesianLimit).

    Why is this bad?
    A string or list makes Pilz's CartesianLimitsAggregator throw InvalidParameterTypeException
    (ROS 2) while loading the planner; a zero or negative speed or acceleration gives LIN and
    CIRC trajectories that never move or cannot be built.

    Example:
    cartesian_limits:
      max_trans_vel: 1.0
      max_trans_acc: 2.25
      max_trans_dec: 5.0
      max_rot_vel: 1.57

    Use instead:
    cartesian_limits:
      max_trans_vel: 1.0
      max_trans_acc: 2.25
      max_trans_dec: -5.0
      max_rot_vel: 1.57
    """

    code, name, severity, target = "P102", "invalid-cartesian-limit", Severity.ERROR, Target.PILZ

    def check(self, ctx: PilzContext) -> Iterator[Finding]:
        for key in (*POSITIVE, "max_trans_dec"):
            node = child(ctx.limits, key)
            if node is None:
                continue
            value = as_scalar(node)
            if value is None:
                yield ctx.finding_at(self, *position(node), f"{key} is {shape(node)}, not a number")
                continue
            number = value.number()
            if number is None:
                yield ctx.finding_at_scalar(self, value, f"{key} is {value.text!r}, not a number", hint="e.g. 1.0")
            elif key in POSITIVE and number <= 0:
                yield ctx.finding_at_scalar(self, value, f"{key} is {value.text}: it must be positive")
            elif key == "max_trans_dec" and number >= 0:
                yield ctx.finding_at_scalar(
                    self,
                    value,
                    f"max_trans_dec is {value.text}: Pilz takes a deceleration as a negative number",
                    hint=f"write -{value.text.lstrip('+')}" if number > 0 else "e.g. -5.0",
                )
