from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class MissingLimit(Rule):
    """
    What it does:
    Reports a revolute or prismatic joint without a <limit> element.

    Why is this bad?
    urdfdom rejects revolute and prismatic joints without limits; parsers that accept
    them use 0..0, and the joint cannot move at all in planning.

    Example:
    <joint name="elbow" type="revolute">...<axis xyz="0 0 1"/></joint>

    Use instead:
    <limit lower="-2.9" upper="2.9" effort="30" velocity="2.0"/>
    or type="continuous" for a joint that turns without end.
    """

    code, name, severity, target = "U201", "missing-limit", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            if joint.type in ("revolute", "prismatic") and joint.limit() is None:
                yield ctx.finding(
                    self,
                    joint.el,
                    f"{joint.type} joint '{joint.name}' has no <limit>",
                    hint='add <limit lower="..." upper="..." effort="..." velocity="..."/>',
                )
