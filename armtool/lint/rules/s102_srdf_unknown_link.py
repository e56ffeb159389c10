from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext
from armtool.suggest import closest


class SrdfUnknownLink(Rule):
    """
    What it does:
    Reports an SRDF link reference that names a link the URDF lacks: a group's <link name>,
    a <chain base_link/tip_link>, or a <virtual_joint child_link>.

    Why is this bad?
    MoveIt skips the unknown link: a chain with an unknown end adds no joints at all, so the
    "arm" group is empty or incomplete and every IK request fails; a virtual joint whose
    child link is unknown makes the whole robot model fail to load.

    Example:
    <group name="arm"><chain base_link="base_link" tip_link="tool_0"/></group>

    Use instead:
    <group name="arm"><chain base_link="base_link" tip_link="tool0"/></group>
    """

    code, name, severity, target = "S102", "srdf-unknown-link", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        if ctx.urdf is None:
            return
        known = ctx.urdf.link_names
        urdf_name = ctx.urdf.path.name
        refs: list[tuple[etree._Element, str, str]] = []
        for group in ctx.elements("group"):
            owner = f"group '{group.get('name')}'"
            for el in group:
                tag = local_tag(el)
                if tag == "link":
                    refs.append((el, "name", f"{owner}: link"))
                elif tag == "chain":
                    refs.append((el, "base_link", f"{owner}: chain base_link"))
                    refs.append((el, "tip_link", f"{owner}: chain tip_link"))
        for el in ctx.elements("virtual_joint"):
            refs.append((el, "child_link", f"virtual_joint '{el.get('name')}': child_link"))
        for el, attr, what in refs:
            name = el.get(attr)
            if name is None or name in known:
                continue
            match = closest(name, known)
            if match:
                hint = f'use an existing link name, e.g. {attr}="{match}"'
            else:
                hint = _hint(ctx, el.get("tip_link"), attr, known)
            yield ctx.finding(
                self,
                el,
                f"{what} '{name}' is not in {urdf_name}" + (f" (did you mean '{match}'?)" if match else ""),
                attr=attr,
                hint=hint,
            )


def _hint(ctx: SrdfContext, tip: str | None, attr: str, known: set[str]) -> str:
    """For an unknown chain base, the links above the tip are the candidates; for a virtual joint, the root."""
    assert ctx.urdf is not None
    if attr == "base_link" and tip is not None and tip in known:
        up = ctx.urdf.ancestors(tip)
        if up:
            shown = ", ".join(up[-3:][::-1]) if len(up) > 3 else ", ".join(reversed(up))
            return f"base_link must be a link above tip_link '{tip}', e.g. {shown}"
    if attr == "child_link":
        roots = ctx.urdf.root_links()
        if roots:
            return f'the virtual joint attaches the URDF\'s root link: child_link="{roots[0]}"'
    return "fix the name, or add the link to the URDF"
