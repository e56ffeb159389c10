from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import JOINT_TYPES, UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.suggest import did_you_mean


class UnknownJointType(Rule):
    """
    What it does:
    Reports a joint whose type is missing or is not one of revolute, continuous,
    prismatic, fixed, floating, planar.

    Why is this bad?
    urdfdom rejects the joint and with it the model.

    Example:
    <joint name="j1" type="rotational">

    Use instead:
    <joint name="j1" type="revolute">
    """

    code, name, severity, target = "U105", "unknown-joint-type", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            if joint.type in JOINT_TYPES:
                continue
            if joint.type is None:
                yield ctx.finding(
                    self,
                    joint.el,
                    f"joint '{joint.name}' has no type",
                    hint='add type="revolute" (or another joint type)',
                )
                continue
            yield ctx.finding(
                self,
                joint.el,
                f"joint '{joint.name}' has unknown type '{joint.type}'{did_you_mean(joint.type, JOINT_TYPES)}",
                attr="type",
                hint="one of: " + ", ".join(JOINT_TYPES),
            )
