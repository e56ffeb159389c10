from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class LimitMissingAttribute(Rule):
    """
    What it does:
    Reports a <limit> of a revolute or prismatic joint without `effort` or `velocity`.

    Why is this bad?
    urdfdom requires both and rejects the model ("joint limit: no effort"); some other
    parsers default them to 0, which makes the joint unplannable or unmovable.

    Example:
    <limit lower="-1.57" upper="1.57"/>

    Use instead:
    <limit lower="-1.57" upper="1.57" effort="30" velocity="2.0"/>
    """

    code, name, severity, target = "U202", "limit-missing-attribute", Severity.ERROR, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            limit = joint.limit()
            if joint.type not in ("revolute", "prismatic") or limit is None:
                continue
            missing = [a for a in ("effort", "velocity") if joint.limits.get(a) is None]
            if missing:
                yield ctx.finding(
                    self,
                    limit,
                    f"joint '{joint.name}': <limit> lacks {' and '.join(missing)}",
                    hint="add " + " ".join(f'{a}="..."' for a in missing) + " (the servo's rated values; never 0)",
                )
