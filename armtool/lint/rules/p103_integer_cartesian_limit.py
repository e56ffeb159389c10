from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, FixSafety, Severity
from armtool.lint.moveit_context import PilzContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.params import as_scalar, child


class IntegerCartesianLimit(Rule):
    """
    What it does:
    Reports a Pilz Cartesian limit written as a whole number (`max_trans_vel: 1`) in a ROS 2
    package (an ament package.xml, or a ROS 2 parameter file). Pilz's own README example writes
    them so; ROS 1 reads an integer parameter as a double.

    Why is this bad?
    Pilz's CartesianLimitsAggregator (MoveIt 2) declares each limit as a double parameter;
    rcl types `1` as an integer, so declaring it throws InvalidParameterTypeException ("Error
    getting parameter ..., check parameter type in YAML file") and the Pilz planner does not
    load.

    Example:
    cartesian_limits:
      max_trans_vel: 1
      max_trans_dec: -5

    Use instead:
    cartesian_limits:
      max_trans_vel: 1.0
      max_trans_dec: -5.0

    Fix safety:
    Safe: `1` becomes `1.0`, the same number as a double.
    """

    code, name, severity, target = "P103", "integer-cartesian-limit", Severity.ERROR, Target.PILZ
    fix_safety = FixSafety.SAFE

    def check(self, ctx: PilzContext) -> Iterator[Finding]:
        if ctx.ros != 2:
            return
        for key in ctx.KEYS:
            value = as_scalar(child(ctx.limits, key))
            if value is None or value.kind != "int":
                continue
            yield ctx.integer_finding(self, value, key, "Pilz")
