from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class MultipleRoots(Rule):
    """
    What it does:
    Reports a model with more than one root link (a link that is no joint's child),
    or with none at all (every link has a parent: a kinematic loop).

    Why is this bad?
    A URDF is one tree. urdfdom refuses several roots; tools that pick one root silently
    drop the other tree, so a gripper or a sensor disappears from planning.

    Example:
    A <link name="camera_link"/> that no joint attaches.

    Use instead:
    <joint name="camera_joint" type="fixed"><parent link="base_link"/><child link="camera_link"/></joint>
    """

    code, name, severity, target = "U103", "multiple-roots", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        if not ctx.links:
            return
        roots = ctx.root_links()
        if not roots:
            yield ctx.finding(
                self,
                ctx.root,
                "no root link: every link is some joint's child, so the joints form a loop",
                hint="URDF is a tree; break the loop (model closed chains with mimic joints or in the controller)",
            )
            return
        if len(roots) == 1:
            return
        for name in roots[1:]:
            el = ctx.link(name)
            assert el is not None
            yield ctx.finding(
                self,
                el,
                f"link '{name}' is a second root (the first is '{roots[0]}'): no joint attaches it",
                attr="name",
                hint=f'add a joint with <child link="{name}"/>, or check for a misspelled child link name',
            )
