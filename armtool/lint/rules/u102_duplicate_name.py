from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target

if TYPE_CHECKING:
    from lxml import etree


class DuplicateName(Rule):
    """
    What it does:
    Reports two links, or two joints, with the same name (often a xacro macro called twice
    without a prefix).

    Why is this bad?
    urdfdom rejects the model; parsers that do not keep the first or the last one silently.

    Example:
    <xacro:finger/> <xacro:finger/>   (both make link "finger")

    Use instead:
    <xacro:finger prefix="left_"/> <xacro:finger prefix="right_"/>
    """

    code, name, severity, target = "U102", "duplicate-name", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        groups = (("link", list(ctx.link_name.items())), ("joint", [(j.el, j.name) for j in ctx.joints]))
        for kind, named in groups:
            first_of: dict[str, etree._Element] = {}
            for el, name in named:
                if name is None:
                    continue
                if name in first_of:
                    first = ctx.locator.place(first_of[name])
                    yield ctx.finding(
                        self,
                        el,
                        f"{kind} '{name}' is defined twice (first at line {first.line})",
                        attr="name",
                        hint=f"rename one of the two {kind}s",
                    )
                else:
                    first_of[name] = el
