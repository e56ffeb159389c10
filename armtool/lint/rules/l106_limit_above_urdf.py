from __future__ import annotations

import math
from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.numbers import half_unit_written, parse_floats
from armtool.lint.rule import Rule, Target


class LimitAboveUrdf(Rule):
    """
    What it does:
    Reports a joint_limits.yaml limit wider than the URDF's: `max_velocity` above the URDF's
    `<limit velocity>`, `max_position` above its `upper`, `min_position` below its `lower`.
    A value equal to the URDF's at the precision it is written in is not beyond it: the
    tolerance is half a unit in the last digit written (`max_velocity: 5.23599` against
    `velocity="${radians(300)}"` = 5.2359878: 5.23599 ± 0.000005 holds it), not a percentage, so a
    real excess (20 % above, copied from a sibling robot, or a factor of 3) is still reported. A
    whole number (`3`) shows no precision and gets none.

    Why is this bad?
    joint_limits.yaml overrides the URDF in MoveIt (RobotModelLoader replaces the bounds), so
    MoveIt plans motions the URDF says the joint cannot make. The URDF describes the hardware:
    ros2_control's joint limiters and the drivers enforce its limits, so the controller clips or
    aborts the trajectory. The file is meant to tighten limits, or to add what the URDF cannot
    hold (acceleration, jerk).

    Example:
    <limit lower="-2.0" upper="2.0" effort="150" velocity="2.0"/>   (URDF)
    joint2: {has_velocity_limits: true, max_velocity: 3.0}          (joint_limits.yaml)

    Use instead:
    joint2: {has_velocity_limits: true, max_velocity: 2.0}
    """

    code, name, severity, target = "L106", "limit-above-urdf", Severity.WARNING, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        if ctx.urdf is None:
            return
        for entry in ctx.doc.joints:
            for joint_name in entry.name.matches(ctx.urdf_joint_names())[:1]:
                joint = ctx.urdf.joint(joint_name)
                if joint is None or joint.limit_el is None:
                    continue
                urdf = {k: _number(joint.limits.get(k)) for k in ("lower", "upper", "velocity")}
                checks = [
                    ("max_velocity", entry.limit("max_velocity"), urdf["velocity"], 1, "velocity"),
                    ("max_position", entry.limit("max_position"), urdf["upper"], 1, "upper"),
                    ("min_position", entry.limit("min_position"), urdf["lower"], -1, "lower"),
                ]
                if joint.type == "continuous":
                    checks = checks[:1]
                for key, mine, theirs, sign, attr in checks:
                    if mine is None or theirs is None or (key == "max_velocity" and theirs <= 0):
                        continue
                    value = entry.values[key]
                    written = half_unit_written(value.text)
                    if value.tag == "!degrees":
                        written = math.radians(written)
                    if sign * (mine - theirs) > max(1e-9 * max(1.0, abs(theirs)), written):
                        yield ctx.finding_at_scalar(
                            self,
                            value,
                            f"joint '{entry.name.written}': {key} {value.text} is beyond the URDF's {attr}="
                            f'"{joint.limits.get(attr)}"{ctx.urdf_note()}',
                            hint=f"{'at most' if sign > 0 else 'at least'} the URDF's {theirs:g} (the hardware's limit), or fix the URDF",
                        )


def _number(text: str | None) -> float | None:
    values = parse_floats(text or "")
    return values[0] if values and len(values) == 1 and math.isfinite(values[0]) else None
