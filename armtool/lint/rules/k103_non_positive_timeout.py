from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext, not_positive
from armtool.lint.rule import Rule, Target


class NonPositiveTimeout(Rule):
    """
    What it does:
    Reports a kinematics_solver_timeout that is zero, negative, or not a number.

    Why is this bad?
    The timeout (in seconds) is how long the solver may search for one IK answer. Zero or
    less leaves no time at all, so every request fails; a quoted or malformed value is
    rejected by the parameter server, and MoveIt silently uses its default.

    Example:
    arm:
      kinematics_solver_timeout: 0

    Use instead:
    arm:
      kinematics_solver_timeout: 0.005
    """

    code, name, severity, target = "K103", "non-positive-timeout", Severity.ERROR, Target.KINEMATICS

    def check(self, ctx: KinematicsContext) -> Iterator[Finding]:
        for group, item, what in not_positive(ctx, "kinematics_solver_timeout"):
            yield ctx.finding_at(
                self,
                item.line,
                item.column,
                f"group '{group.name}': kinematics_solver_timeout {what}",
                hint="set a positive time in seconds, e.g. kinematics_solver_timeout: 0.005 (5 ms)",
            )
