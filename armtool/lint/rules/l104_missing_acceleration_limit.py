from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target


class MissingAccelerationLimit(Rule):
    """
    What it does:
    Reports a joint of a planning group (an SRDF group's revolute, prismatic or continuous
    joint that is neither mimic nor passive) without an acceleration limit in joint_limits.yaml:
    no entry, `has_acceleration_limits: false` or missing, or no `max_acceleration`. ROS 1
    packages are not checked (MoveIt 1's time parameterization falls back to 1 rad/s²).

    Why is this bad?
    A URDF has no acceleration limits, so joint_limits.yaml is their only source. MoveIt 2's
    time-optimal parameterization (TOTG, the default since MoveIt 2.7) refuses to time a
    trajectory of such a joint: "No acceleration limit was defined for joint joint1! You have to
    define acceleration limits in the URDF or joint_limits.yaml", and the plan fails (Humble
    still fell back to 1 rad/s² with a warning); Pilz's planners fail too ("acceleration limit
    not set for group"). The Setup Assistant writes `has_acceleration_limits: false` for every
    joint.

    Example:
    joint_limits:
      joint1:
        has_velocity_limits: true
        max_velocity: 2.0
        has_acceleration_limits: false
        max_acceleration: 0

    Use instead:
    joint_limits:
      joint1:
        has_velocity_limits: true
        max_velocity: 2.0
        has_acceleration_limits: true
        max_acceleration: 5.0
    """

    code, name, severity, target = "L104", "missing-acceleration-limit", Severity.WARNING, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        if ctx.ros == 1:
            return
        groups_of: dict[str, list[str]] = {}
        for group, joints in ctx.active_group_joints().items():
            for joint in joints:
                groups_of.setdefault(joint, []).append(group)
        at = ctx.doc.joint_limits_at or (1, 1)
        for joint, groups in groups_of.items():
            entry = ctx.doc.entry_for(joint)
            in_groups = f"(group{'s' if len(groups) > 1 else ''} {', '.join(groups)})"
            hint = f"add has_acceleration_limits: true and max_acceleration: <rad/s² or m/s²> for {joint}"
            if entry is None:
                yield ctx.finding_at(
                    self, *at, f"joint '{joint}' {in_groups} has no entry: no acceleration limit", hint=hint
                )
                continue
            flag = entry.values.get("has_acceleration_limits")
            if flag is None or flag.flag() is not True:
                said = "is missing" if flag is None else f"is {flag.text}"
                line, column = (flag.line, flag.column) if flag is not None else (entry.line, entry.column)
                yield ctx.finding_at(
                    self,
                    line,
                    column,
                    f"joint '{entry.name.written}' {in_groups}: has_acceleration_limits {said}: no acceleration limit",
                    hint=hint,
                )
            elif entry.limit("max_acceleration") is None:
                yield ctx.finding_at(
                    self,
                    entry.line,
                    entry.column,
                    f"joint '{entry.name.written}' {in_groups} sets has_acceleration_limits but no max_acceleration",
                    hint=hint,
                )
