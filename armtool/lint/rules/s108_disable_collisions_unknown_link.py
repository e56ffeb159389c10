from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext
from armtool.suggest import closest


class DisableCollisionsUnknownLink(Rule):
    """
    What it does:
    Reports a <disable_collisions> (or <enable_collisions>) entry whose link1 or link2 names
    a link the URDF lacks.

    Why is this bad?
    MoveIt ignores the entry with a warning. The pair it was meant for (usually adjacent
    links that always touch) stays enabled, so every state is "in collision" and planning
    fails; or the entry is stale after a rename and the matrix no longer matches the robot.

    Example:
    <disable_collisions link1="base_link" link2="shoulder_lnk" reason="Adjacent"/>

    Use instead:
    <disable_collisions link1="base_link" link2="shoulder_link" reason="Adjacent"/>
    """

    code, name, severity, target = "S108", "disable-collisions-unknown-link", Severity.WARNING, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        urdf = ctx.urdf
        if urdf is None:
            return
        known = urdf.link_names
        for tag in ("disable_collisions", "enable_collisions"):
            for el in ctx.elements(tag):
                for attr in ("link1", "link2"):
                    name = el.get(attr)
                    if name is None or name in known:
                        continue
                    match = closest(name, known)
                    yield ctx.finding(
                        self,
                        el,
                        f"{tag} {attr} '{name}' is not in {urdf.path.name}"
                        + (f" (did you mean '{match}'?)" if match else ""),
                        attr=attr,
                        hint=f'use the existing link: {attr}="{match}"'
                        if match
                        else "remove the entry, or regenerate the collision matrix (MoveIt Setup Assistant)",
                    )
