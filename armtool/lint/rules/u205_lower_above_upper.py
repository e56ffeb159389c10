from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


class LowerAboveUpper(Rule):
    """
    What it does:
    Reports a revolute or prismatic joint whose lower limit is greater than its upper limit.

    Why is this bad?
    No position satisfies the limits: every IK solution and every state is "out of bounds".

    Example:
    <limit lower="1.57" upper="-1.57" effort="30" velocity="2"/>

    Use instead:
    <limit lower="-1.57" upper="1.57" effort="30" velocity="2"/>
    """

    code, name, severity, target = "U205", "lower-above-upper", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            limit = joint.limit()
            if limit is None or joint.type not in ("revolute", "prismatic"):
                continue
            lo, hi = parse_floats(joint.limits.get("lower", "0")), parse_floats(joint.limits.get("upper", "0"))
            if lo and hi and len(lo) == 1 and len(hi) == 1 and lo[0] > hi[0]:
                yield ctx.finding(
                    self,
                    limit,
                    f"joint '{joint.name}': lower limit {joint.limits.get('lower', '0')} is above upper limit {joint.limits.get('upper', '0')}",
                    attr="lower",
                    hint="swap lower and upper",
                )
