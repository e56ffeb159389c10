from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target


class ScalingFactorOutOfRange(Rule):
    """
    What it does:
    Reports `default_velocity_scaling_factor` or `default_acceleration_scaling_factor` outside
    (0, 1].

    Why is this bad?
    The factors are fractions of the limits. MoveIt refuses a factor outside (0, 1] where it
    applies it ("Invalid max_velocity_scaling_factor 1.5 specified, defaulting to 1.0") and
    plans at full speed instead: a 0 meant as "slow" becomes the fastest motion.

    Example:
    default_velocity_scaling_factor: 10   # meant 10 %

    Use instead:
    default_velocity_scaling_factor: 0.1
    """

    code, name, severity, target = "L107", "scaling-factor-out-of-range", Severity.WARNING, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        for key, value in ctx.doc.scaling.items():
            number = value.number()
            if number is not None and not 0 < number <= 1:
                yield ctx.finding_at_scalar(
                    self,
                    value,
                    f"{key} {value.text} is outside (0, 1]: MoveIt falls back to 1.0 (full speed)",
                    hint="a fraction of the limits, e.g. 0.1 for 10 %",
                )
