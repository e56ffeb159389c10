from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext

# srdfdom's Model::loadVirtualJoints drops a virtual joint without one of these, with its message.
REQUIRED = (
    ("name", "Name of virtual joint is not specified"),
    ("child_link", "Child link of virtual joint is not specified"),
    ("parent_frame", "Parent frame of virtual joint is not specified"),
    ("type", "Type of virtual joint is not specified"),
)


class VirtualJointIncomplete(Rule):
    """
    What it does:
    Reports a `<virtual_joint>` without `name`, `child_link`, `parent_frame` or `type`.

    Why is this bad?
    srdfdom (Model::loadVirtualJoints) logs an error ("Name of virtual joint is not specified",
    and likewise for the child link, parent frame and type) and drops the element, so MoveIt
    builds no virtual joint: a mobile base's planar or floating joint is gone, and groups or
    states naming the joint lose it.

    Example:
    <virtual_joint type="floating" parent_frame="odom" child_link="base_link"/>

    Use instead:
    <virtual_joint name="odom_joint" type="floating" parent_frame="odom" child_link="base_link"/>
    """

    code, name, severity, target = "S113", "virtual-joint-incomplete", Severity.WARNING, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        for el in ctx.elements("virtual_joint"):
            missing = [attr for attr, _ in REQUIRED if not (el.get(attr) or "").strip()]
            if not missing:
                continue
            said = dict(REQUIRED)[missing[0]]
            yield ctx.finding(
                self,
                el,
                f'<virtual_joint> without {", ".join(missing)}: srdfdom drops it ("{said}")',
                hint="give it " + " ".join(f'{attr}="..."' for attr in missing),
            )
