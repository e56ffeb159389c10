from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext
from armtool.suggest import closest


class EndEffectorParentLink(Rule):
    """
    What it does:
    Reports an <end_effector> whose parent_link is missing or not a link of the URDF, or,
    when parent_group is given, is not one of the links of that group (usually its tip).

    Why is this bad?
    MoveIt logs "Group 'arm' was specified as parent group for end-effector 'hand' but it
    does not include the parent link" and cannot attach the end effector to the arm: the
    interactive marker, grasp planning and `setEndEffectorLink` then use the wrong link.

    Example:
    <end_effector name="hand" group="hand" parent_group="arm" parent_link="panda_link0"/>

    Use instead:
    <end_effector name="hand" group="hand" parent_group="arm" parent_link="panda_link8"/>
    """

    code, name, severity, target = "S105", "end-effector-parent-link", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        urdf = ctx.urdf
        if urdf is None:
            return
        for el in ctx.elements("end_effector"):
            owner = f"end_effector '{el.get('name')}'"
            link = el.get("parent_link")
            if link is None:
                yield ctx.finding(
                    self,
                    el,
                    f"{owner} has no parent_link",
                    hint='add parent_link="...": the arm link the end effector is mounted on',
                )
                continue
            if link not in urdf.link_names:
                joint = urdf.joint(link)
                group = el.get("parent_group")
                if joint is not None and joint.child:
                    note = f" ('{link}' is a joint; its child link is '{joint.child}')"
                    hint = f'use the link: parent_link="{joint.child}"'
                elif (match := closest(link, urdf.link_names)) is not None:
                    note = f" (did you mean '{match}'?)"
                    hint = f'use an existing link name, e.g. parent_link="{match}"'
                elif group is not None and group in ctx.groups and (tip := _tip(ctx, group)):
                    note = ""
                    hint = f"parent_group '{group}' ends at '{tip}': parent_link=\"{tip}\""
                else:
                    note = ""
                    hint = "name the link the end effector is mounted on (usually the arm's flange or tool link)"
                yield ctx.finding(
                    self,
                    el,
                    f"{owner}: parent_link '{link}' is not a link in {urdf.path.name}{note}",
                    attr="parent_link",
                    hint=hint,
                )
                continue
            parent_group = el.get("parent_group")
            if parent_group is None or parent_group not in ctx.groups:
                continue
            links = ctx.group_links(parent_group)
            if not links or link in links:
                continue
            tip = _tip(ctx, parent_group)
            yield ctx.finding(
                self,
                el,
                f"{owner}: parent_link '{link}' is not a link of parent_group '{parent_group}'",
                attr="parent_link",
                hint=(f'use the group\'s tip, e.g. parent_link="{tip}", ' if tip else "")
                + "or add the link to the group",
            )


def _tip(ctx: SrdfContext, group: str) -> str | None:
    """Where a group ends: its chain's tip_link, else its deepest link when all lie on one branch."""
    assert ctx.urdf is not None
    for el in ctx.groups[group]:
        tip: str | None = el.get("tip_link")
        if local_tag(el) == "chain" and tip in ctx.urdf.link_names:
            return tip
    links = ctx.group_links(group)
    for cand in sorted(links):
        if links - {cand} <= set(ctx.urdf.ancestors(cand)):
            return cand
    return None
