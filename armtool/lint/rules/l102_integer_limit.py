from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, FixSafety, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target
from armtool.moveit.joint_limits import KEY_TYPES


class IntegerLimit(Rule):
    """
    What it does:
    Reports a limit or scaling factor written as a whole number (`max_velocity: 1`) in a
    joint_limits.yaml that MoveIt 2 loads. Only ROS 2 packages (an ament package.xml, or a ROS 2
    parameter file) are checked: ROS 1's roscpp reads an integer parameter as a double
    (ros::param getImpl(double&) converts XmlRpc TypeInt), so `1` is fine for MoveIt 1.

    Why is this bad?
    ROS 2 parameters are typed, and rcl's YAML parser types `1` as an integer. MoveIt's
    RobotModelLoader declares `max_velocity`, `max_acceleration`, `max_jerk` and the positions as
    PARAMETER_DOUBLE, so move_group stops with `InvalidParameterTypeException: parameter
    'robot_description_planning.joint_limits.joint1.max_velocity' has invalid type: expected
    [double] got [integer]` (or, where the parameter was declared from the file first, logs the
    error and drops the joint's limits). MoveIt's Setup Assistant writes such values itself
    when the URDF's are whole numbers (moveit/moveit2 #2776, #3716).

    Example:
    joint_limits:
      joint1:
        has_velocity_limits: true
        max_velocity: 1

    Use instead:
    joint_limits:
      joint1:
        has_velocity_limits: true
        max_velocity: 1.0

    Fix safety:
    Safe: `1` becomes `1.0`, the same number as a double.
    """

    code, name, severity, target = "L102", "integer-limit", Severity.ERROR, Target.JOINT_LIMITS
    fix_safety = FixSafety.SAFE

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        if ctx.ros != 2:
            return
        items = [
            (key, f"joint '{e.name.written}': {key}", value) for e in ctx.doc.joints for key, value in e.values.items()
        ]
        items += [(key, key, value) for key, value in ctx.doc.scaling.items()]
        for key, what, value in items:
            if value.kind != "int" or (key in KEY_TYPES and KEY_TYPES[key] != "double"):
                continue
            yield ctx.integer_finding(self, value, what, "MoveIt 2")
