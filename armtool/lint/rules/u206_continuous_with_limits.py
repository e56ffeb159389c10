from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.context import UrdfContext
from armtool.lint.finding import Finding, Severity
from armtool.lint.numbers import parse_floats
from armtool.lint.rule import Rule, Target


class ContinuousWithLimits(Rule):
    """
    What it does:
    Reports a continuous joint whose <limit> has `lower` or `upper`.

    Why is this bad?
    Continuous joints ignore position limits, so the arm may turn through a cable or a
    hard stop that the author meant to respect. Usually "revolute" was meant.

    Example:
    <joint name="wrist" type="continuous"><limit lower="-3.14" upper="3.14" effort="10" velocity="3"/>

    Use instead:
    <joint name="wrist" type="revolute"><limit lower="-3.14" upper="3.14" effort="10" velocity="3"/>
    """

    code, name, severity, target = "U206", "continuous-with-limits", Severity.WARNING, Target.URDF

    def check(self, ctx: UrdfContext) -> Iterator[Finding]:
        for joint in ctx.joints:
            limit = joint.limit()
            if joint.type != "continuous" or limit is None:
                continue
            present = [a for a in ("lower", "upper") if joint.limits.get(a) is not None]
            if present and all((parse_floats(joint.limits.get(a)) or [1.0]) == [0.0] for a in present):
                continue  # lower="0" upper="0": a CAD exporter's placeholder, nothing was meant
            if present:
                yield ctx.finding(
                    self,
                    limit,
                    f"continuous joint '{joint.name}' has {' and '.join(present)} limits, which continuous joints ignore",
                    attr=present[0],
                    hint='use type="revolute" to enforce them, or drop lower/upper',
                )
