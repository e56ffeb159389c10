from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from armtool.lint.finding import Finding, Severity
from armtool.lint.locate import local_tag
from armtool.lint.rule import Rule, Target
from armtool.lint.srdf_context import SrdfContext
from armtool.suggest import closest


class UnknownGroup(Rule):
    """
    What it does:
    Reports a group name that the SRDF does not define: a subgroup (<group name> inside a
    <group>), an <end_effector group> or <end_effector parent_group>, or a <group_state group>.

    Why is this bad?
    MoveIt cannot build a group whose subgroup is missing ("unmet subgroup dependencies"),
    ignores the end effector, and drops the named pose, each with only a log message:
    the planner later reports that the group or the pose does not exist.

    Example:
    <group_state name="home" group="manipulater">...</group_state>

    Use instead:
    <group_state name="home" group="manipulator">...</group_state>
    """

    code, name, severity, target = "S103", "unknown-group", Severity.ERROR, Target.SRDF

    def check(self, ctx: SrdfContext) -> Iterator[Finding]:
        known = set(ctx.groups)
        refs: list[tuple[etree._Element, str, str]] = []
        for group in ctx.elements("group"):
            for el in group:
                if local_tag(el) == "group":
                    refs.append((el, "name", f"group '{group.get('name')}': subgroup"))
        for el in ctx.elements("end_effector"):
            refs.append((el, "group", f"end_effector '{el.get('name')}': group"))
            refs.append((el, "parent_group", f"end_effector '{el.get('name')}': parent_group"))
        for el in ctx.elements("group_state"):
            refs.append((el, "group", f"group_state '{el.get('name')}': group"))
        for el, attr, what in refs:
            name = el.get(attr)
            if name is None or name in known:
                continue
            match = closest(name, known)
            if match is None:
                # "lf" for "lf_leg": a unique group that starts with the name
                starts = [g for g in known if g.startswith(name) and g[len(name) : len(name) + 1] in ("_", "-")]
                match = starts[0] if len(starts) == 1 else None
            if match:
                hint = f'use an existing group name, e.g. {attr}="{match}"'
            elif known:
                hint = "groups defined here: " + ", ".join(sorted(known))
            else:
                hint = 'define the group with <group name="...">'
            yield ctx.finding(
                self,
                el,
                f"{what} '{name}' is not defined in this SRDF" + (f" (did you mean '{match}'?)" if match else ""),
                attr=attr,
                hint=hint,
            )
