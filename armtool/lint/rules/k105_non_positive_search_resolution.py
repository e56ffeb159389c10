from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext, not_positive
from armtool.lint.rule import Rule, Target


class NonPositiveSearchResolution(Rule):
    """
    What it does:
    Reports a kinematics_solver_search_resolution that is zero, negative, or not a number.

    Why is this bad?
    The search resolution is the step (radians or metres) by which solvers that search over
    redundant joints (IKFast, KDL on 7-DOF arms) sample the free joint. Zero or less makes
    that search loop forever or not at all, and a non-number is ignored for the default.

    Example:
    arm:
      kinematics_solver_search_resolution: 0

    Use instead:
    arm:
      kinematics_solver_search_resolution: 0.005
    """

    code, name, severity, target = "K105", "non-positive-search-resolution", Severity.ERROR, Target.KINEMATICS

    def check(self, ctx: KinematicsContext) -> Iterator[Finding]:
        for group, item, what in not_positive(ctx, "kinematics_solver_search_resolution"):
            yield ctx.finding_at(
                self,
                item.line,
                item.column,
                f"group '{group.name}': kinematics_solver_search_resolution {what}",
                hint="set a positive step, e.g. kinematics_solver_search_resolution: 0.005",
            )
