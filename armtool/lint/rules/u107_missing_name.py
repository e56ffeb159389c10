from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class MissingRequired(Rule):
    """
    What it does:
    Reports a <robot>, link or joint without a name, and a joint without <parent link> or <child link>.

    Why is this bad?
    urdfdom rejects the model; nothing else can refer to an unnamed element.

    Example:
    <joint name="j1" type="fixed"><parent link="base"/></joint>

    Use instead:
    <joint name="j1" type="fixed"><parent link="base"/><child link="tool"/></joint>
    """

    code, name, severity, target = "U107", "missing-required", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        if not ctx.root.get("name"):
            yield ctx.finding(
                self, ctx.root, "<robot> has no name (urdfdom rejects it)", hint='add name="..." to <robot>'
            )
        for link, name in ctx.link_name.items():
            if not name:
                yield ctx.finding(self, link, "<link> has no name", hint='add name="..."')
        for joint in ctx.joints:
            if not joint.name:
                yield ctx.finding(self, joint.el, "<joint> has no name", hint='add name="..."')
            if joint.parent and joint.child:
                continue  # both named (joint.parent is <parent link>, read once per file)
            for role in ("parent", "child"):
                el = joint.parent_el if role == "parent" else joint.child_el
                if el is None or not el.get("link"):
                    yield ctx.finding(
                        self,
                        joint.el if el is None else el,
                        f"joint '{joint.name}' has no <{role} link=\"...\"/>",
                        hint=f'add <{role} link="LINK"/>',
                    )
