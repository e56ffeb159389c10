from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class InvalidPilzYaml(Rule):
    """
    What it does:
    Reports a pilz_cartesian_limits.yaml that is not valid YAML. Reported by the loader.

    Why is this bad?
    MoveIt's launch loads it with a YAML parser (MoveItConfigsBuilder.pilz_cartesian_limits):
    the launch stops.

    Example:
    cartesian_limits:
      max_trans_vel: 1.0
     max_trans_acc: 2.25

    Use instead:
    cartesian_limits:
      max_trans_vel: 1.0
      max_trans_acc: 2.25
    """

    code, name, severity, target = "P001", "invalid-pilz-yaml", Severity.ERROR, Target.PILZ

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
