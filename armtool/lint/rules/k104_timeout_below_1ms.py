from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.kinematics_context import KinematicsContext, as_number
from armtool.lint.numbers import fmt
from armtool.lint.rule import Rule, Target

ONE_MS = 0.001


class TimeoutBelow1ms(Rule):
    """
    What it does:
    Reports a kinematics_solver_timeout above zero but below 1 ms (0.001).

    Why is this bad?
    The timeout is in seconds. Values like 0.0005 usually mean that 5 ms were meant and a
    zero slipped in (or milliseconds were converted twice): half a millisecond is too
    short for KDL or TRAC-IK to converge, so IK "fails" on reachable poses.

    Example:
    arm:
      kinematics_solver_timeout: 0.0005

    Use instead:
    arm:
      kinematics_solver_timeout: 0.005
    """

    code, name, severity, target = "K104", "timeout-below-1ms", Severity.WARNING, Target.KINEMATICS

    def check(self, ctx: KinematicsContext) -> Iterator[Finding]:
        for group in ctx.groups:
            item = group.settings.get("kinematics_solver_timeout")
            if item is None:
                continue
            seconds = as_number(item.value)
            if seconds is None or not 0 < seconds < ONE_MS:
                continue
            meant = seconds
            while meant < ONE_MS:
                meant *= 10
            yield ctx.finding_at(
                self,
                item.line,
                item.column,
                f"group '{group.name}': kinematics_solver_timeout {fmt(seconds)} s = {fmt(seconds * 1000)} ms; "
                f"did you mean {fmt(meant)} ({fmt(meant * 1000)} ms)?",
                hint=f"the timeout is in seconds: kinematics_solver_timeout: {fmt(meant)}",
            )
