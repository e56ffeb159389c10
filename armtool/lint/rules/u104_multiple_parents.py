from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class MultipleParents(Rule):
    """
    What it does:
    Reports a link that is the child of more than one joint.

    Why is this bad?
    A link can hang from only one joint in a tree; urdfdom rejects the model and other
    parsers keep one of the joints without saying which.

    Example:
    <joint name="a"><parent link="base"/><child link="tool"/></joint>
    <joint name="b"><parent link="arm"/><child link="tool"/></joint>

    Use instead:
    One joint per child link; close loops in the controller, or use a mimic joint.
    """

    code, name, severity, target = "U104", "multiple-parents", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for child, joints in ctx.joints_by_child.items():
            if len(joints) < 2:
                continue
            first = joints[0].name
            for joint in joints[1:]:
                el = joint.child_el
                assert el is not None
                yield ctx.finding(
                    self,
                    el,
                    f"link '{child}' already has parent joint '{first}'; joint '{joint.name}' is a second parent",
                    attr="link",
                    hint="give each link exactly one parent joint",
                )
