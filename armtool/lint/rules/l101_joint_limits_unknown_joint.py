from __future__ import annotations

from collections.abc import Iterator

from armtool.lint.finding import Finding, Severity
from armtool.lint.moveit_context import JointLimitsContext
from armtool.lint.rule import Rule, Target
from armtool.suggest import closest


class JointLimitsUnknownJoint(Rule):
    """
    What it does:
    Reports a joint in joint_limits.yaml that the URDF does not have. A key written with a
    launch substitution (`$(var tf_prefix)joint_1`) is matched with the substitution's value
    when a xacro argument of that name is known, else by the rest of the name.

    Why is this bad?
    MoveIt looks up `joint_limits.<joint>` only for the joints of its robot model
    (RobotModelLoader::configure walks the model's joints), so an entry under a misspelt name is
    never read: the joint it was meant for keeps the URDF's limits, and gets no acceleration
    limit at all.

    Example:
    joint_limits:
      shoulder_pan:          # the URDF calls it shoulder_pan_joint
        has_acceleration_limits: true
        max_acceleration: 5.0

    Use instead:
    joint_limits:
      shoulder_pan_joint:
        has_acceleration_limits: true
        max_acceleration: 5.0
    """

    code, name, severity, target = "L101", "joint-limits-unknown-joint", Severity.WARNING, Target.JOINT_LIMITS

    def check(self, ctx: JointLimitsContext) -> Iterator[Finding]:
        if ctx.urdf is None:
            return
        known = ctx.urdf_joint_names()
        for entry in ctx.doc.joints:
            if entry.name.matches(known):
                continue
            match = closest(entry.name.bare, known)
            note = entry.name.note()
            yield ctx.finding_at(
                self,
                entry.line,
                entry.column,
                f"joint '{entry.name.written}' is not in the URDF{ctx.urdf_note()}"
                + (f" (did you mean '{match}'?)" if match else "")
                + (f"; {note}" if note else ""),
                hint=f"rename it to '{match}'" if match else "joints: " + ", ".join(sorted(known)[:20]),
            )
