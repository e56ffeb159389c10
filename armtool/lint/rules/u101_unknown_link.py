from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.suggest import closest


class UnknownLink(Rule):
    """
    What it does:
    Reports a joint whose <parent link> or <child link> names a link that does not exist.

    Why is this bad?
    The parser builds a disconnected model: the links after the joint float free, the
    chain from base to tool does not exist, and IK reports "no solution" or "no chain".

    Example:
    <joint name="elbow" type="revolute"><parent link="lnk2"/><child link="link3"/>...

    Use instead:
    <joint name="elbow" type="revolute"><parent link="link2"/><child link="link3"/>...
    """

    code, name, severity, target = "U101", "unknown-link", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            for role in ("parent", "child"):
                name = joint.parent if role == "parent" else joint.child
                if name is None or name in ctx.link_names:
                    continue
                match = closest(name, ctx.link_names)
                el = joint.parent_el if role == "parent" else joint.child_el
                assert el is not None
                yield ctx.finding(
                    self,
                    el,
                    f"joint '{joint.name}': {role} link '{name}' does not exist"
                    + (f" (did you mean '{match}'?)" if match else ""),
                    attr="link",
                    hint=f'use an existing link name, e.g. link="{match}"' if match else "add the link or fix the name",
                )
