from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext
from armtool.suggest import closest


class SrdfUnknownJoint(Rule):
    """
    What it does:
    Reports an SRDF joint reference that names a joint the URDF lacks: a group's
    <joint name>, a <passive_joint name>, or a <group_state>'s <joint name>.

    Joints declared by the SRDF's own <virtual_joint> count as known.

    Why is this bad?
    MoveIt drops the unknown joint with an error in the log: the group silently loses a
    degree of freedom (IK then "finds no solution" or ignores an axis), a passive joint is
    planned as active, and a named pose such as "home" leaves that joint where it was.

    Example:
    <group name="arm"><joint name="shoulder_pan"/><joint name="elbow_jont"/></group>

    Use instead:
    <group name="arm"><joint name="shoulder_pan"/><joint name="elbow_joint"/></group>
    """

    code, name, severity, target = "S101", "srdf-unknown-joint", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        if ctx.urdf is None:
            return
        virtual = {el.get("name") for el in ctx.elements("virtual_joint") if el.get("name")}
        known = ctx.urdf.joint_names | {v for v in virtual if v}
        urdf_name = ctx.urdf.path.name
        refs: list[tuple[etree._Element, str]] = []
        for group in ctx.elements("group"):
            for el in group:
                if local_tag(el) == "joint":
                    refs.append((el, f"group '{group.get('name')}'"))
        for el in ctx.elements("passive_joint"):
            refs.append((el, "passive_joint"))
        for state in ctx.elements("group_state"):
            for el in state:
                if local_tag(el) == "joint":
                    refs.append((el, f"group_state '{state.get('name')}'"))
        for el, owner in refs:
            name = el.get("name")
            if name is None or name in known:
                continue
            kind = _virtual_kind(el.get("value"))
            match = None if kind else closest(name, known)
            if kind:
                roots = ctx.urdf.root_links()
                child = roots[0] if len(roots) == 1 else "ROOT_LINK"
                hint = (
                    f'its value looks like a {kind} base pose: declare it, e.g. <virtual_joint name="{name}" '
                    f'type="{kind}" parent_frame="world" child_link="{child}"/>'
                )
            elif match:
                hint = f'use an existing joint name, e.g. name="{match}"'
            else:
                hint = "fix the name, or add the joint to the URDF (or declare a <virtual_joint>)"
            yield ctx.finding(
                self,
                el,
                f"{owner}: joint '{name}' is not in {urdf_name}" + (f" (did you mean '{match}'?)" if match else ""),
                attr="name",
                hint=hint,
            )


def _virtual_kind(value: str | None) -> str | None:
    """'floating' for a 7-number value (x y z qx qy qz qw), 'planar' for 3 (x y theta), else None."""
    numbers = parse_floats(value)
    if numbers is None:
        return None
    return {7: "floating", 3: "planar"}.get(len(numbers))
