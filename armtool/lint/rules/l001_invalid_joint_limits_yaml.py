from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.rule import Rule, Target


class InvalidJointLimitsYaml(Rule):
    """
    What it does:
    Reports a joint_limits.yaml that is not valid YAML. Reported by the loader.

    Why is this bad?
    MoveIt's launch loads the file with a YAML parser (MoveItConfigsBuilder's load_yaml, or
    rcl's parameter-file parser): the launch stops, and move_group never starts.

    Example:
    joint_limits:
      joint1:
        has_velocity_limits: true
       max_velocity: 2.0

    Use instead:
    joint_limits:
      joint1:
        has_velocity_limits: true
        max_velocity: 2.0
    """

    code, name, severity, target = "L001", "invalid-joint-limits-yaml", Severity.ERROR, Target.JOINT_LIMITS

    def check(self, ctx: object) -> Iterator[Finding]:
        return iter(())
