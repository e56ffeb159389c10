from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target


class JointLimitsRobotNotFound(Rule):
    """
    What it does:
    Says that the joint_limits.yaml of a MoveIt config package (it has a .setup_assistant or an
    SRDF) was checked on its own: no SRDF was found for it (as
    for kinematics.yaml: `--srdf`, the configuration's `srdf` table, `.setup_assistant`, the
    SRDF beside it) and no URDF either (`--urdf`, the configuration's `urdf` table, the one robot
    of its package's urdf/ or robots/ with all its joints), or that SRDF's URDF was not found. Its
    joint names, the limits against the URDF's and the acceleration limits the planning groups
    need were not checked.

    Why is this bad?
    Nothing is wrong with the file itself; the checks that need the robot did not run.

    Example:
    armtool lint ur_moveit_config/config/joint_limits.yaml   (the SRDF needs name:= to expand)

    Use instead:
    armtool lint --srdf srdf/ur.srdf.xacro --xacro-arg name:=ur config/joint_limits.yaml
    """

    code, name, severity, target = "L002", "joint-limits-robot-not-found", Severity.INFO, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        if ctx.urdf is not None or not ctx.in_moveit_package:
            return
        what = "no SRDF or URDF found for it" if ctx.srdf is None else f"the URDF of {ctx.srdf.path.name} was not found"
        line, column = ctx.doc.joint_limits_at or (1, 1)
        yield ctx.finding_at(
            self,
            line,
            column,
            f"joint names and limits not compared with the robot: {what}",
            hint="pass --srdf (and --urdf), or --moveit-config DIR for the package",
        )
