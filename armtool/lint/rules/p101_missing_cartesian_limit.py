from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import PilzContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.params import child, items
from armtool.suggest import closest


class MissingCartesianLimit(Rule):
    """
    What it does:
    Reports a `cartesian_limits` mapping that lacks one of max_trans_vel, max_trans_acc,
    max_trans_dec and max_rot_vel (a misspelt key counts as missing, with did-you-mean).

    Why is this bad?
    Pilz's CartesianLimitsAggregator declares each of the four with no default and logs
    "Parameter '...max_trans_dec', is not set in the config file" when one is missing; LIN and
    CIRC then refuse every request for lack of Cartesian limits.

    Example:
    cartesian_limits:
      max_trans_vel: 1.0
      max_trans_acc: 2.25
      max_rot_vel: 1.57

    Use instead:
    cartesian_limits:
      max_trans_vel: 1.0
      max_trans_acc: 2.25
      max_trans_dec: -5.0
      max_rot_vel: 1.57
    """

    code, name, severity, target = "P101", "missing-cartesian-limit", Severity.ERROR, Target.PILZ

    def check(self, ctx: PilzContext) -> Iterator[Finding]:
        written = [k for k, _, _ in items(ctx.limits)]
        line, column = ctx.limits_at or (1, 1)
        for key in ctx.KEYS:
            if child(ctx.limits, key) is not None:
                continue
            stray = closest(key, [k for k in written if k not in ctx.KEYS])
            yield ctx.finding_at(
                self,
                line,
                column,
                f"cartesian_limits has no {key}"
                + (f" (did you mean '{stray}'? it is written '{stray}')" if stray else ""),
                hint=f"rename '{stray}' to {key}"
                if stray
                else f"add {key}: <value> (see pilz_industrial_motion_planner's docs)",
            )
